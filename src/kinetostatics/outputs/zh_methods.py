# ruff: noqa: E501  (the Chinese texts of the translation table are long lines)
"""The Chinese texts of the graded methods' chapters and pictures (issue 38: the instant
centres, the force polygons, the gears, the balancing moment, the cam's design), keyed by
their English text; :mod:`.zh` adds them to its table (looked up by :func:`.lang.tr`)."""

from __future__ import annotations

ZH: dict[str, str] = {}
# issue 38, the instant centres' picture (outputs/plotting/centres.py)
ZH.update(
    {
        "outside the drawing: {items}": "图幅以外：{items}",
        "at infinity (direction): {items}": "位于无穷远处（方向）：{items}",
        "not found by Kennedy's theorem: {items}": "三心定理无法求得：{items}",
    }
)

# issue 38, the free body and force polygon of an Assur group (outputs/plotting/forces.py)
ZH.update(
    {
        "free body of {group}": "{group} 的示力体图",
        "force polygon, {mu} = {v} N/mm": "力多边形，{mu} = {v} N/mm",
        "closure error |ΣF| = {c} N ({r} of the largest force, {f} N)": "闭合误差 |ΣF| = {c} N（为最大力 {f} N 的 {r}）",
    }
)

# issue 38, the gear chapter (outputs/report/gears.py; the notes are methods/gears.py's)
ZH.update(
    {
        "{n}. Gears": "{n}. 齿轮传动",
        "Standard involute teeth: each value with its formula, lengths in {unit}. "
        "h_a*: addendum coefficient, c*: clearance coefficient, x: profile shift "
        "coefficient (positive away from the gear's axis), α': working pressure angle.": "渐开线标准齿廓：各量均列出计算公式与数值，长度单位为 {unit}。h_a*：齿顶高系数，c*：顶隙系数，x：变位系数（远离齿轮轴线为正），α'：啮合角。",
        "{n}.{k} Gear pair {joint} ({mesh})": "{n}.{k} 齿轮副 {joint}（{mesh}）",
        "Gear pair {joint}: geometry": "齿轮副 {joint} 的几何尺寸",
        "formula and value": "公式与数值",
        "external mesh": "外啮合",
        "internal mesh": "内啮合",
        "rack and pinion": "齿轮齿条",
        "annulus": "内齿轮",
        "module": "模数",
        "pressure angle": "压力角",
        "addendum coefficient": "齿顶高系数",
        "clearance coefficient": "顶隙系数",
        "number of teeth of gear {n} ({link})": "齿轮 {n}（{link}）的齿数",
        "profile shift coefficient of gear {n}": "齿轮 {n} 的变位系数",
        "pitch radius of gear {n}": "齿轮 {n} 的分度圆半径",
        "base radius of gear {n}": "齿轮 {n} 的基圆半径",
        "tip radius of gear {n}": "齿轮 {n} 的齿顶圆半径",
        "root radius of gear {n}": "齿轮 {n} 的齿根圆半径",
        "tooth thickness on the pitch circle of gear {n}": "齿轮 {n} 的分度圆齿厚",
        "pressure angle at the tip circle of gear {n}": "齿轮 {n} 的齿顶圆压力角",
        "least profile shift without undercut of gear {n}": "齿轮 {n} 不根切的最小变位系数",
        "pitch": "齿距",
        "base pitch": "基圆齿距（法向齿距）",
        "standard centre distance": "标准中心距",
        "centre distance of the file's pitch circles": "按文件分度圆半径的中心距",
        "height of the pinion's centre above the rack's reference line": "齿轮中心至齿条分度线的距离",
        "pitch radius of the pinion in the file": "文件中齿轮的分度圆半径",
        "working pressure angle": "啮合角",
        "working centre distance": "实际中心距",
        "centre distance modification coefficient": "中心距变动系数",
        "tip reduction coefficient": "齿顶高降低系数",
        "contact ratio": "重合度",
        "least number of teeth without undercut": "不根切的最少齿数",
        "gear {n} ({link}) is undercut: x_{n} = {x} < x_min{n} = {x_min} (z_{n} = {z}, "
        "z_min = {z_min}); a shift x_{n} ≥ {x_min} avoids it": "齿轮 {n}（{link}）发生根切：x_{n} = {x} < x_min{n} = {x_min}（z_{n} = {z}，z_min = {z_min}）；取变位系数 x_{n} ≥ {x_min} 可避免根切",
        "ε_α = {eps} < 1: one pair of teeth leaves before the next engages (the mesh is not "
        "continuous)": "ε_α = {eps} < 1：前一对轮齿脱离啮合时后一对尚未进入啮合（传动不连续）",
        "the shifted pair works at α' = {alpha_w} and a' = {a_w} without backlash; the file's "
        "pitch circles are the reference circles, and the motion, which reads only the ratio, is "
        "the same": "变位齿轮副无侧隙啮合时啮合角 α' = {alpha_w}，中心距 a' = {a_w}；文件中的齿轮半径为分度圆半径，运动只取决于传动比，不受影响",
        "the annulus has no undercut limit; the interference of internal teeth is not checked": "内齿轮无根切极限；未校核内啮合的齿廓干涉",
        "the pinion's number of teeth is not given (key teeth): its module and tooth geometry "
        "are unknown": "未给出齿轮的齿数（键 teeth）：其模数与齿廓尺寸未知",
        "{joint}: {why}": "{joint}：{why}",
    }
)

# issue 38, the chapters of the graded methods (outputs/report/methods.py, plotting/cam.py)
ZH.update(
    {
        "{n}. The balancing moment, three ways": "{n}. 平衡力矩的三种求法",
        "The balancing effort {effort} of the driver {driver} (at its pair {joint}) checked twice. Joukowski's lever (杠杆法): every load turned by +90° (counter-clockwise) and applied at the image of its point in the velocity polygon (image in m/s, pole at the origin); its moment about the pole is image × turned force = F·v, a couple M on a link turning at ω gives M·ω. The polygon is in equilibrium with the driver's M_b·ω₁. The power method (功率法): M_b·ω₁ + Σ(F·v + M·ω) = 0 from the loads' generalized forces. Columns: F the load (N), P its point (mm), F′ the force turned by +90° (N), p its image (= v_P, m/s), M_p = p × F′ its moment about the pole (W = N·m/s).": "原动件 {driver}（运动副 {joint}）的平衡力矩 {effort} 用两种方法校核。儒可夫斯基杠杆法：将各力转过 +90°（逆时针）后作用于速度多边形中其作用点的影像（影像单位 m/s，极点为原点）；其对极点之矩为 影像 × 转向力 = F·v，角速度为 ω 的构件上的力偶 M 给出 M·ω。速度多边形与原动件的 M_b·ω₁ 相平衡。功率法：由各载荷的广义力，M_b·ω₁ + Σ(F·v + M·ω) = 0。各列：F 为载荷（N），P 为其作用点（mm），F′ 为转过 +90° 的力（N），p 为其影像（= v_P，m/s），M_p = p × F′ 为对极点之矩（W = N·m/s）。",
        "The lever and power methods are frictionless: they are compared with the frictionless column {effort}.": "杠杆法与功率法均不计摩擦：与不计摩擦的列 {effort} 比较。",
        "sum": "合计",
        "{n}.{k} Position {pos} (φ = {phi}°)": "{n}.{k} 位置 {pos}（φ = {phi}°）",
        "Position {pos}: the lever's terms": "位置 {pos}：杠杆上的各项",
        "M_b by the lever = {lever} {unit}, by the power method = {power} {unit}, from the solution = {solution} {unit} (ω₁ = {speed}); relative differences: lever–solution {e1}, power–solution {e2}, lever–power {e3}.": "杠杆法 M_b = {lever} {unit}，功率法 M_b = {power} {unit}，动态静力分析解 M_b = {solution} {unit}（ω₁ = {speed}）；相对差：杠杆法–解 {e1}，功率法–解 {e2}，杠杆法–功率法 {e3}。",
        "{n}. Instant centres": "{n}. 速度瞬心",
        "The N(N−1)/2 instant centres (速度瞬心) P_ij: a pair gives its own (a pin's centre; a slide's lies at infinity normal to it), Kennedy's theorem (三心定理) the others, each where two lines through known centres (or the normal of a higher pair) meet. Coordinates in mm in the frame's axes; a centre at infinity is given by its direction. The velocities the centres give are checked against the analysis.": "N(N−1)/2 个速度瞬心 P_ij：运动副直接给出其瞬心（转动副在其中心；移动副在垂直于导路的无穷远处），其余由三心定理求得，即过已知瞬心的两条直线（或高副的公法线）的交点。坐标单位 mm，取机架坐标轴；无穷远处的瞬心以其方向表示。由瞬心求得的速度与分析结果核对。",
        "{n}.{k} Position {pos}": "{n}.{k} 位置 {pos}",
        "Position {pos}: the instant centres with the mechanism.": "位置 {pos}：机构及其速度瞬心。",
        "Position {pos}: instant centres": "位置 {pos}：速度瞬心",
        "bodies": "构件",
        "found how": "求法",
        "pair {joint} ({kind})": "运动副 {joint}（{kind}）",
        "Kennedy: {lines}": "三心定理：{lines}",
        "; at infinity along {angle}°": "；位于 {angle}° 方向的无穷远处",
        "not found": "未求得",
        "{found} of {total} centres found; from ω of {ref} = {omega} rad/s the centres give every body's ω and velocity within {err} (relative) of the analysis.": "求得 {total} 个瞬心中的 {found} 个；由 {ref} 的 ω = {omega} rad/s，瞬心给出的各构件 ω 与速度与分析结果的相对差不超过 {err}。",
        "cam": "凸轮副",
        "{n}. The cam's design": "{n}. 凸轮机构设计",
        "From the cam's own law and dimensions: the follower's s–φ, v–φ, a–φ diagrams (per unit cam speed: v = ω·ds/dφ, a = ω²·d²s/dφ²), the pressure angle α(φ) at the file's base radius, the least radius of curvature of the pitch curve (the roller must be smaller), the least base radius for the allowable pressure angle [α], and the cam drawn at a round scale.": "由凸轮自身的运动规律与尺寸求得：从动件的 s–φ、v–φ、a–φ 线图（按单位凸轮角速度：v = ω·ds/dφ，a = ω²·d²s/dφ²），文件基圆半径下的压力角 α(φ)，理论廓线的最小曲率半径（滚子半径须小于它），许用压力角 [α] 下的最小基圆半径，以及按整数比例尺绘制的凸轮。",
        "{n}.{k} Cam {joint} ({what})": "{n}.{k} 凸轮 {joint}（{what}）",
        "{motion} {follower} follower": "{motion}{follower}从动件",
        "knife": "尖顶",
        "roller": "滚子",
        "flat": "平底",
        "Cam {joint}": "凸轮 {joint}",
        "base radius (file)": "基圆半径（文件）",
        "roller radius (file)": "滚子半径（文件）",
        "allowable pressure angle": "许用压力角",
        "[α] from": "[α] 取自",
        "the file (the cam joint's design: pressure_angle_max)": "文件（凸轮副的 design: pressure_angle_max）",
        "the default: the textbook's 30° (give the cam joint design: pressure_angle_max for another)": "默认值：教材的 30°（另取时在凸轮副中写 design: pressure_angle_max）",
        "the caller": "调用者给定",
        "largest pressure angle": "最大压力角",
        "… at the cam angle": "……所在凸轮转角",
        "least radius of curvature of the pitch curve": "理论廓线的最小曲率半径",
        "least radius of curvature of the profile": "凸轮廓线的最小曲率半径",
        "roller limit (no undercut: r_r < ρ_min)": "滚子半径上限（不失真：r_r < ρ_min）",
        "the file's roller is below the limit": "文件的滚子半径小于上限",
        "least base radius for [α]": "[α] 下的最小基圆半径",
        "found by": "求法",
        "closed form": "解析式",
        "bisection": "二分法",
        "the file's base radius keeps |α| ≤ [α]": "文件的基圆半径满足 |α| ≤ [α]",
        "Cam {joint}: s–φ, v–φ, a–φ diagrams and the pressure angle α–φ.": "凸轮 {joint}：s–φ、v–φ、a–φ 线图与压力角 α–φ 曲线。",
        "Cam {joint}: the working profile and the pitch curve at the scale μ_l.": "凸轮 {joint}：按比例尺 μ_l 绘制的实际廓线与理论廓线。",
        "cam angle φ, deg": "凸轮转角 φ，°",
        "working profile": "实际廓线",
        "pitch curve": "理论廓线",
        "base circle r_b = {r} mm": "基圆 r_b = {r} mm",
    }
)

# issue 38, the chapter of the force polygons (outputs/report/forces.py)
ZH.update(
    {
        "{n}. Force polygons of the Assur groups": "{n}. 各杆组的力多边形",
        "The graphical force analysis (图解法), group by group in the order of the solution: the last Assur group first, the driving link last. Per group its free body (the loads, weights, inertia forces and couples of its links, the reactions of the groups already solved: known; the reactions at its outer pairs: solved) and its force polygon, the vectors chained tip to tail at the round scale μ_F, which closes because the group is in equilibrium. F_Rij is the force of link i on link j. Points P in mm in the frame's axes; vectors (F_x, F_y) in N.": "图解法力分析，按求解顺序逐组进行：先最后一个杆组，最后为原动件。每组给出其受力图（各构件的外载荷、重力、惯性力与惯性力偶，已求杆组传来的约束反力为已知；其外运动副处的约束反力为待求）及其力多边形：各力矢量按整数比例尺 μ_F 首尾相接，因杆组处于平衡而封闭。F_Rij 为构件 i 对构件 j 的作用力。作用点 P 以 mm 计（机架坐标系），矢量 (F_x, F_y) 以 N 计。",
        "The forces are the frictionless solution's first.": "先给出不计摩擦时的各力。",
        " (with friction)": "（计摩擦）",
        "vector, N": "矢量，N",
        "known/solved": "已知/待求",
        "known": "已知",
        "solved": "待求",
        "group {name}": "杆组 {name}",
        "Position {pos}: {name}": "位置 {pos}：{name}",
        "{title}: its forces": "{title}：各力",
        "μ_F = {mu} N/mm; closure error |ΣF| = {c} N ({e} of the largest force, {big} N); moment error {m}.": "μ_F = {mu} N/mm；封闭误差 |ΣF| = {c} N（为最大力 {big} N 的 {e}）；力矩误差 {m}。",
    }
)

# issue 38, the chapter of the vector equations (outputs/report/vectors.py)
ZH.update(
    {
        "{n}. Vector equations": "{n}. 矢量方程图解法",
        "The velocity and acceleration equations of the vector-polygon method, group by group in the order of the solution: each pair of a group equates its two links' views of its point. Per term: its direction, its magnitude (the formula where it is known before the group is solved, \"?\" for the group's two unknowns) and its value from the solution. a^n normal, a^t tangential, a^r relative, a^k Coriolis (2ω × v_r) acceleration; ω, α counter-clockwise positive. The closure residual is |Σ left − Σ right| over the largest term.": "矢量方程图解法的速度与加速度方程，按求解顺序逐个杆组列出：杆组中每个运动副令其两构件上该点的运动相等。每一项给出方向、大小（杆组求解前已知者写出其公式，杆组的两个未知量记为“?”）以及求解所得的数值。a^n 为法向加速度，a^t 为切向加速度，a^r 为相对加速度，a^k 为哥氏加速度（2ω × v_r）；ω、α 以逆时针为正。闭合残差为 |Σ左 − Σ右| 与最大项之比。",
        "{letters} dyad {links}": "{letters} 型Ⅱ级杆组 {links}",
        "triad {links}": "Ⅲ级杆组 {links}",
        "known": "已知",
        "the axis of {joint}": "{joint} 导路",
        "the tangent of the pitch curve": "理论廓线的切线",
        "the tangent of the profile": "凸轮廓线的切线",
        "the tangent of the face": "平底",
        "its centre of curvature": "其曲率中心",
        "the line of action": "啮合线",
        "the face": "平底",
        "{group}:": "{group}：",
        "{kind} at the pair {joint}: {equation}": "{kind}（运动副 {joint}）：{equation}",
        "Velocity": "速度",
        "Acceleration": "加速度",
        "direction": "方向",
        "magnitude": "大小",
        "value, {unit}": "数值，{unit}",
        "Solved: {solved}; closure residual {res} (relative).": "解得：{solved}；闭合残差 {res}（相对）。",
        "Not written: {note}": "未列出：{note}",
        "not written for this pair type": "此类运动副的项未列出",
        "accelerations not written for this pair type": "此类运动副的加速度项未列出",
    }
)
