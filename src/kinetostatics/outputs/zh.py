# ruff: noqa: E501  (the Chinese texts of the translation table are long lines)
"""The Chinese texts of the report and the pictures, keyed by their English text
(looked up by :func:`.lang.tr`)."""

from __future__ import annotations

from .zh_methods import ZH as _METHODS
from .zh_sizing import ZH as _SIZING

# -- the Chinese texts ---------------------------------------------------------------------
ZH: dict[str, str] = {}
ZH.update(
    {
        " (means over the analysed rows)": "（各分析位置的平均）",
        "1. Data": "1. 原始数据",
        "2. Structure": "2. 机构结构分析",
        "3. Results over the cycle": "3. 全周期计算结果",
        "4. The mechanism": "4. 机构运动简图",
        "5. Kinematics and forces at the course-design positions": "5. 各设计位置的运动分析与力分析",
        "6. Curves over the cycle": "6. 全周期曲线",
        "7. Velocity and acceleration polygons": "7. 速度多边形与加速度多边形",
        "8. Polar diagrams of the joint loads": "8. 运动副反力极坐标图",
        "{n}. Flywheel": "{n}. 飞轮设计",
        "Acceleration polygon at position {pos}.": "位置 {pos} 的加速度多边形。",
        "Accelerations: angular accelerations (rad/s², counter-clockwise +) and point "
        "accelerations (m/s²), components and magnitude": "加速度：构件角加速度（rad/s²，逆时针为正）与各点加速度（m/s²），分量与大小",
        "Assumptions:": "假设：",
        "Assur group (class and members)": "阿苏尔杆组（级别与构件）",
        "Assur groups in solve order": "按求解顺序的阿苏尔杆组",
        "Course-design report: {name}": "机械原理课程设计报告：{name}",
        "Drawn from the exact results to the stated scales μ_v and μ_a (true scale when "
        "printed at 100 %): p is the pole, lower-case letters the points (a2, a3: the "
        "coincident points of links 2 and 3), n and k the ends of normal and Coriolis "
        "components.": "按精确结果以所注比例尺 μ_v、μ_a 绘制（按 100 % 打印即为真实比例）：p 为极点，小写字母为各点（a2、a3：构件 2、3 上的重合点），n、k 为法向分量与科氏分量的端点。",
        "Drivers": "原动件",
        "Energy diagram ΔW–φ: its range ΔW_max sizes the flywheel.": "能量指示图 ΔW–φ：其变化范围 ΔW_max 决定飞轮转动惯量。",
        "Equivalent driving moment M_d (constant) and resisting moment M_r over the cycle; "
        "the shaded areas are the surplus and deficit work.": "一个周期内的等效驱动力矩 M_d（常数）与等效阻力矩 M_r；阴影面积为盈功与亏功。",
        "Equivalent moments and the energy ΔW at the course positions (interpolated on the "
        "design's {n} positions)": "各设计位置的等效力矩与能量 ΔW（由设计所用 {n} 个位置插值）",
        "F_ij: link i on link j at the joint; FI, MI: inertia; G: weight": "F_ij：构件 i 作用于构件 j 的运动副反力；FI：惯性力；MI：惯性力偶矩；G：重力",
        " (with friction)": "（计摩擦）",
        "Flywheel: data": "飞轮：已知数据",
        "Flywheel: result": "飞轮：计算结果",
        "Instantaneous and cycle efficiency of the drive {driver}.": "原动件 {driver} 的瞬时效率与周期效率。",
        "Joints (the reaction is the force of link i on link j)": "运动副（反力为构件 i 对构件 j 的作用力）",
        "Links (numbers as in the pictures; the frame last)": "构件（编号与图中一致；机架编号最后）",
        "Loads": "载荷",
        "Motion diagram of the output ({name}): position, velocity, acceleration; the shaded "
        "zone is where the process load acts.": "输出构件（{name}）的运动线图：位移、速度、加速度；阴影区为工作阻力作用区间。",
        "Parameters": "参数",
        "Dimension synthesis: the parameters computed from others (file's units)": (
            "尺寸综合：由其他参数算出的参数（文件的单位）"
        ),
        # the 12-position drawing's title block and caption (outputs/plotting/sheet.py)
        "name": "名称",
        "scale": "比例",
        "date": "日期",
        "drawn by": "制图",
        "heavy: working position {w}; thin: the course positions; phantom line: the limit "
        "positions {lim}; red: the paths of {paths}; μ_l = {mu:g} m/mm": (
            "粗实线：工作位置 {w}；细实线：各设计位置；双点画线：极限位置 {lim}；"
            "红线：{paths} 的轨迹；μ_l = {mu:g} m/mm"
        ),
        "Position angle: every position is named by the angle φ of the first driver "
        "({driver}), measured counter-clockwise from +x in [0, 360)°; link angles θ likewise. "
        "travel is the rotation from position 1 in the sense of motion. Course-design "
        "positions 1…12 are every 30° of travel from the analysis start (φ₁ = {start}°); k′ "
        "are the positions where a load switches (start and end of cutting), after position "
        "k.": "位置角：各位置以第一原动件（{driver}）的转角 φ 表示，自 +x 轴逆时针量取，取值 [0, 360)°；构件角 θ 同此约定。travel 为沿运动方向自位置 1 起的转角。设计位置 1…12 自分析起点（φ₁ = {start}°）起每隔 30° 取一个；k′ 为载荷切换的位置（切削开始与结束），位于位置 k 之后。",
        " The analysis runs {n} turns of {driver}: k/t is position k of turn t.": " 分析覆盖 {driver} 的 {n} 转：k/t 表示第 t 转的位置 k。",
        "Positions: driver angle φ and link angles θ (deg, 0–360, counter-clockwise from +x), "
        "points ({unit})": "位置：原动件转角 φ 与构件角 θ（°，0–360，自 +x 逆时针），各点坐标（{unit}）",
        "Reaction of each revolute joint in the frame of the link that receives it, over the "
        "cycle (numbers: course positions).": "各转动副反力在受力构件坐标系中的极坐标图（数字为设计位置）。",
        "Rows of `results.csv` (the column CSV row) at the positions {labels}; values to 5 "
        "significant digits (0: below 1e-9 of the largest value of its unit in the table, "
        "round-off), column names as in the CSV; |v|, |a|, |F| are the magnitudes of the "
        "components before them. Wide tables are split into groups of columns, each repeating "
        "the position, its CSV row and its angle.": "下表为 `results.csv` 在位置 {labels} 的行（CSV row 列）；数值取 5 位有效数字（0 表示小于表中同单位最大值的 1e-9，即舍入误差），列名与 CSV 相同；|v|、|a|、|F| 为其前两个分量的合成大小。较宽的表格分为若干列组，每组重复位置、CSV 行号与位置角。",
        "Source: `{source}`. Units of the file: {units}. Everything below is in SI unless "
        "stated (lengths of points in {lu}). Gravity: ({gx}, {gy}) m/s².": "来源：`{source}`。文件单位：{units}。以下除注明外均为国际单位（点的长度单位为 {lu}）。重力加速度：({gx}, {gy}) m/s²。",
        "The energy method: J_F = ΔW_max / (ω_m² δ), ΔW(φ) = ∫ (M_d − M_r) dφ from position "
        "1, with M_r the equivalent resisting moment on the crank (the balancing moment at the "
        "nominal speed, link inertia included) and M_d its cycle mean. Angles φ are driver "
        "angles in [0, 360)°.": "能量法：J_F = ΔW_max / (ω_m² δ)，ΔW(φ) = ∫ (M_d − M_r) dφ 自位置 1 起积分，其中 M_r 为曲柄上的等效阻力矩（额定转速下的平衡力矩，含构件惯性），M_d 为其周期平均值。φ 为原动件转角，取值 [0, 360)°。",
        "The mechanism at position {pos} with the paths of its moving pins (to the scale μ_l "
        "stated on it).": "位置 {pos} 的机构运动简图及各活动铰链点的轨迹（比例尺 μ_l 见图）。",
        "Units: lengths of points and strokes in the file's unit ({unit}); velocities in m/s, "
        "accelerations in m/s², forces in N, moments in N·m, angles in deg, angular velocities "
        "in rad/s.": "单位：点的坐标与行程采用文件单位（{unit}）；速度 m/s，加速度 m/s²，力 N，力矩 N·m，角度 °，角速度 rad/s。",
        "Velocities: angular velocities (rad/s, counter-clockwise +) and point velocities "
        "(m/s), components and magnitude": "速度：构件角速度（rad/s，逆时针为正）与各点速度（m/s），分量与大小",
        "Velocity polygon at position {pos}.": "位置 {pos} 的速度多边形。",
        "acceleration polygon": "加速度多边形",
        "velocity polygon": "速度多边形",
        "active while": "作用条件",
        "acts on": "作用于",
        "at φ (deg)": "所在 φ（°）",
        "centre of mass ({lu})": "质心（{lu}）",
        "clockwise": "顺时针",
        "counter-clockwise": "逆时针",
        "coefficient of speed fluctuation": "速度波动系数",
        "deficit work (M_d < M_r)": "亏功（M_d < M_r）",
        "surplus work (M_d > M_r)": "盈功（M_d > M_r）",
        "driver": "原动件",
        "driver (crank shaft)": "原动件（曲柄轴）",
        "effort at": "驱动力作用处",
        "equivalent driving moment (cycle mean)": "等效驱动力矩（周期平均）",
        "equivalent driving moment M_d = {m} N·m (cycle mean)": "等效驱动力矩 M_d = {m} N·m（周期平均）",
        "equivalent resisting moment M_r (balancing moment)": "等效阻力矩 M_r（平衡力矩）",
        "on": "开始作用",
        "off": "停止作用",
        "flywheel on the crank shaft, less J_e (net)": "装于曲柄轴的飞轮，扣除 J_e（净值）",
        "flywheel on the crank shaft, machine inertia neglected": "装于曲柄轴的飞轮，忽略机构自身惯量",
        "flywheel on the motor shaft": "装于电机轴的飞轮",
        "flywheel on the motor shaft, net": "装于电机轴的飞轮，净值",
        "speed ratio motor : crank": "传动比 电机 : 曲柄",
        "frame": "机架",
        "friction": "摩擦",
        "frictionless": "不计摩擦",
        "with friction (consistent)": "计摩擦（一致解）",
        "independent loops: {n}": "独立回路数：{n}",
        "joint": "运动副",
        "joints and drivers": "运动副与原动件",
        "kind": "类型",
        "largest stored energy at": "最大储能位置",
        "smallest stored energy at": "最小储能位置",
        "link": "构件",
        "links i → j": "构件 i → j",
        "load": "载荷",
        "load events at": "载荷切换位置",
        "machine's equivalent inertia, cycle mean": "机构等效转动惯量，周期平均",
        "machine's equivalent inertia, largest": "机构等效转动惯量，最大值",
        "machine's equivalent inertia, smallest": "机构等效转动惯量，最小值",
        "mass (kg)": "质量（kg）",
        "maximum energy swing": "最大盈亏功",
        "mobility (Grübler–Kutzbach): {m}": "自由度（Grübler–Kutzbach 公式）：{m}",
        "moment on the crank, N·m (sense of motion +)": "曲柄上的力矩，N·m（运动方向为正）",
        "motion (+ counter-clockwise)": "运动（逆时针为正）",
        "no.": "编号",
        "nominal crank speed": "曲柄额定转速",
        "knife-edge": "尖顶",
        "flat-faced": "平底",
        "roller r = {r} mm": "滚子 r = {r} mm",
        "cam {i} (centre {c}, base radius {rb} mm, turning {sense}), {motion} {follower} "
        "follower {j} at {p}": "凸轮 {i}（转动中心 {c}，基圆半径 {rb} mm，{sense} 转向），{motion}{follower}从动件 {j} 于 {p}",
        "oscillating": "摆动",
        "translating": "直动",
        "f = {f}": "f = {f}",
        "parameter": "参数",
        "path of {ref}": "{ref} 的轨迹",
        "points ({lu}, in the link's own frame)": "点（{lu}，构件自身坐标系）",
        "pos.": "位置",
        "position {pos} ({coord})": "位置 {pos}（{coord}）",
        "quantity": "量",
        "reaction": "反力",
        "resisting moment from": "阻力矩依据",
        "rotation φ of {name} from position 1 (φ₁ = {start}°, {sense}), deg": "{name} 自位置 1 起的转角 φ（φ₁ = {start}°，{sense}），°",
        "sense of rotation": "转向",
        "step": "步骤",
        "swing ΔW_max = {s} J": "最大盈亏功 ΔW_max = {s} J",
        "symbol": "符号",
        "travel (deg)": "转过角度（°）",
        "travel of {p} along ({x}, {y}) in [{a}, {b}] {lu}": "{p} 沿 ({x}, {y}) 的位移在 [{a}, {b}] {lu} 内",
        "type": "类型",
        "unit": "单位",
        "value": "数值",
        "value (as in the file)": "数值（同文件）",
        "where": "位置",
        "work per cycle": "每周期功",
        "yes": "是",
        "no": "否",
        "{name}: energy diagram ΔW–φ": "{name}：能量指示图 ΔW–φ",
        "{name}: equivalent driving and resisting moments": "{name}：等效驱动力矩与等效阻力矩",
        "{n} positions analysed (a full cycle: {full})": "共分析 {n} 个位置（完整周期：{full}）",
        "{p} moving along ({x}, {y})": "{p} 沿 ({x}, {y}) 运动时",
        "ΔW(φ) = ∫(M_d − M_r) dφ": "ΔW(φ) = ∫(M_d − M_r) dφ",
        "ΔW, J": "ΔW，J",
        "ΔW_max": "ΔW_max",
        "ΔW_min": "ΔW_min",
        "page": "第页",
        "(printed at 100 %: the scales hold on paper)": "（按 100 % 打印：比例尺在纸上成立）",
        "(reduced to {p} %: divide the scales by {s})": "（缩小至 {p} %：比例尺除以 {s}）",
        "always": "始终",
        " (tabulated)": "（表格给定）",
        "{law} law, peak speed {speed}": "{law} 运动规律，最大速度 {speed}",
        "effort {e}": "驱动力 {e}",
        "driver angle φ in [{a}, {b}]°": "原动件转角 φ 在 [{a}, {b}]° 内",
        "; with friction: no consistent solution at any position (self-locking; approximate "
        "mean {m})": "；计摩擦：任何位置均无一致解（自锁；近似解平均 {m}）",
        "singular position: {group} at φ = {angle}° (condition {c})": "奇异位置：{group} 于 φ = {angle}°（条件数 {c}）",
        "redundant constraints: reactions are the minimum-norm solution": "存在冗余约束：反力取最小范数解",
        " — here there are none": "——此处没有",
        "{n}. Springs and dampers": "{n}. 弹簧与阻尼器",
        "A spring or damper acts between two points along the line that joins them "
        "(its length s), a torsion spring or rotary damper at a revolute on the "
        "rotation of link j relative to link i (its angle s). Its force (moment) f "
        "reduces s when positive (a spring in tension): a spring's is preload + "
        "stiffness·(s − free length), or its table interpolated linearly and held "
        "constant outside; a damper's is damping·ds/dt. Stored energy: 0 at the free "
        "length (at the first value of a table); power f·ds/dt: stored by a spring, "
        "dissipated by a damper. Values in the units of the file.": "弹簧或阻尼器作用于两点之间，沿两点连线（其长度 s）；扭簧或旋转阻尼器作用于转动副，作用于构件 j 相对构件 i 的转动（其转角 s）。其力（力矩）f 为正时使 s 减小（弹簧受拉）：弹簧力为 预紧力 + 刚度·(s − 自由长度)，或按其表格线性插值、表外保持不变；阻尼力为 阻尼系数·ds/dt。储存能量：自由长度处（表格的第一个值处）为 0；功率 f·ds/dt：弹簧储存，阻尼器耗散。数值采用文件的单位。",
        "element": "元件",
        "between": "连接",
        "stiffness": "刚度",
        "free length or angle": "自由长度或自由角",
        "preload": "预紧力",
        "table (s → f)": "表格（s → f）",
        "damping": "阻尼系数",
        "Elements": "弹簧与阻尼器",
        "at revolute {joint}: {j} relative to {i}": "转动副 {joint}：{j} 相对 {i}",
        "Springs and dampers at the course-design positions: length or angle s, force "
        "or moment f (positive reduces s), stored energy (J) and power f·ds/dt (W)": "各设计位置的弹簧与阻尼器：长度或转角 s，力或力矩 f（为正时使 s 减小），储存能量（J）与功率 f·ds/dt（W）",
    }
)


# the pictures: curves, polar diagrams, polygons; the flywheel's assumptions
ZH.update(
    {
        "time, s ({name}: {law} law)": "时间，s（{name}：{law}运动规律）",
        "harmonic": "简谐",
        "polynomial": "多项式",
        "table": "表格",
        "{name} rotation from {start}° ({sense}), deg": "{name} 自 {start}° 起的转角（{sense}），°",
        "{name} travel, mm": "{name} 的位移，mm",
        "relative angle of {name}": "{name} 的相对转角",
        "relative angle": "相对转角",
        "relative angular velocity": "相对角速度",
        "relative angular acceleration": "相对角加速度",
        "relative travel of {name}": "{name} 的相对位移",
        "relative travel": "相对位移",
        "relative velocity": "相对速度",
        "relative acceleration": "相对加速度",
        "s of {point} along {joint}": "{point} 沿 {joint} 的位移 s",
        "s": "位移 s",
        "v = ds/dt": "速度 v = ds/dt",
        "a = d²s/dt²": "加速度 a = d²s/dt²",
        "θ of {name}": "{name} 的转角 θ",
        "ω of {name}": "{name} 的角速度 ω",
        "α of {name}": "{name} 的角加速度 α",
        "θ": "转角 θ",
        "ω": "角速度 ω",
        "α": "角加速度 α",
        "position of {name}": "{name} 的位置",
        "velocity of {name}": "{name} 的速度",
        "acceleration of {name}": "{name} 的加速度",
        "position": "位置",
        "velocity": "速度",
        "acceleration": "加速度",
        "x component": "x 分量",
        "y component": "y 分量",
        "course positions": "设计位置",
        "course positions (turns 1 to {n})": "设计位置（第 1 至 {n} 转）",
        "load switches ({loads})": "载荷切换（{loads}）",
        "{loads} acting": "{loads} 作用区间",
        "output slider": "输出滑块",
        "link {name}": "构件 {name} ",
        "point {name}": "点 {name} ",
        "joint {name}": "运动副 {name} ",
        "{model}: motion diagram of the {what}": "{model}：{what}的运动线图",
        " ({label})": "（{label}）",
        "reaction magnitude |F|, N": "运动副反力大小 |F|，N",
        "{model}: joint reactions": "{model}：运动副反力",
        "without friction": "不计摩擦",
        "with friction, approximate (from frictionless reactions)": "计摩擦，近似解（由不计摩擦的反力求得）",
        "with friction, consistent": "计摩擦，一致解",
        "{label} (cycle mean {mean} {unit})": "{label}（周期平均 {mean} {unit}）",
        "self-locking": "自锁",
        "M, {unit} (counter-clockwise +)": "M，{unit}（逆时针为正）",
        "{model}: driving torque of {driver}": "{model}：{driver} 的平衡力矩 M_b",
        "{model}: driving force of {driver}": "{model}：{driver} 的平衡力 F_b",
        "η = P / P_friction where the drive delivers power (gaps: undefined)": "η = P / P_friction（仅在原动件输入功率处定义，空缺处无定义）",
        "cycle efficiency (mean M / mean M_friction) = {eta}": "周期效率（M 的平均值 / M_friction 的平均值）= {eta}",
        "efficiency η, 1": "效率 η，1",
        "{model}: efficiency of the drive {driver}": "{model}：原动件 {driver} 的效率",
        "no values:\nself-locking at\nevery position": "无数值：\n各位置\n均自锁",
        "{joint}: no consistent friction solution": "{joint}：无计摩擦一致解",
        "{i} on {j}": "{i} 作用于 {j}",
        "in the frame of {link}; max {peak} N": "{link} 坐标系；最大值 {peak} N",
        "F along {link} x, N": "F 沿 {link} 的 x 轴，N",
        "F along {link} y, N": "F 沿 {link} 的 y 轴，N",
        "{model}: polar diagrams of the joint loads": "{model}：运动副反力极坐标图",
        " — numbers: course positions": "——数字为设计位置",
        "pole {p}: points at rest": "极点 {p}：静止的点",
        " ({names})": "（{names}）",
        "{link} at {point}": "{link} 上与 {point} 重合的点",
        "pivot": "固定铰链",
        "⊥ {r}": "⊥ {r}",
        "∥ axis of {j}": "∥ {j} 的导路",
        "⊥ axis of {j}": "⊥ {j} 的导路",
        "∥ {r}, towards {b}": "∥ {r}，指向 {b}",
        "revolute": "转动副",
        "prismatic": "移动副",
        "gear": "齿轮副",
        "rack": "齿轮齿条副",
        "links: {links}": "构件：{links}",
        "balancing moment at the constant nominal crank speed ω_m = {omega_m:.6g} rad/s "
        "(link inertia torques at that speed included)": "平衡力矩按曲柄以额定转速 ω_m = {omega_m:.6g} rad/s 匀速转动计算（含该转速下的构件惯性力矩）",
        "the frictionless balancing moment": "不计摩擦的平衡力矩",
        "the balancing moment with friction (consistent solution)": "计摩擦的平衡力矩（一致解）",
        "{a} on {i}, {b} on {j}": "{i} 上的 {a}，{j} 上的 {b}",
        "friction circle ρ = {rho} mm": "摩擦圆 ρ = {rho} mm",
        "none": "无",
        "axis {axis} of {i}, point {p} of {j}": "{i} 的导路 {axis}，{j} 上的点 {p}",
        ", contact length {l} mm": "，接触长度 {l} mm",
        "force": "力",
        "torque": "力矩",
        "resistance": "工作阻力",
        "driving link {links}": "原动件 {links}",
        "driving links {links}": "原动件 {links}",
        "{n}-link group {links}": "由 {n} 个构件组成的杆组 {links}",
        "moving": "运动条件",
        "travel from": "行程区间起点",
        "travel to": "行程区间终点",
        "angle": "转角区间",
    }
)


# the drive-sizing chapter and the four-quadrant picture (dynamics/drive.py)
ZH.update(
    {
        "motoring": "电动",
        "braking": "制动",
        "rated torque (continuous)": "额定转矩（连续）",
        "peak torque": "峰值转矩",
        "rated speed": "额定转速",
        "motor over the cycle": "一个周期内的电机工作点",
        "motor speed, rpm (sense of motion +)": "电机转速，rpm（运动方向为正）",
        "motor torque, N·m (sense of motion +)": "电机转矩，N·m（运动方向为正）",
        "with friction": "计摩擦",
        "{name}: four-quadrant torque–speed of drive {driver} (ratio {i}, {torque})": "{name}：驱动 {driver} 的四象限转矩–转速图（传动比 {i}，{torque}）",
        "{n}. Drive sizing": "{n}. 驱动选型",
        "The motor turns the driven shaft through a reduction of ratio i and efficiency "
        "η. Its torque T_M = T/(i·η) where the shaft takes power and T_M = T·η/i where "
        "it gives power back, plus the inertia torque (J_m + J_r)·i·α of rotor and "
        "reduction; its speed i·ω. Torques and speeds are positive in the sense of motion.": "电机经传动比为 i、效率为 η 的减速器驱动从动轴。从动轴吸收功率时电机转矩 T_M = T/(i·η)，回馈功率时 T_M = T·η/i，再加上转子与减速器的惯性转矩 (J_m + J_r)·i·α；电机转速为 i·ω。转矩与转速均以运动方向为正。",
        "Drive: data": "驱动：原始数据",
        "Drive: torque, power and speed over the cycle": "驱动：一个周期内的转矩、功率与转速",
        "driving torque from": "驱动转矩取自",
        "reduction ratio (motor speed / driven shaft speed)": "传动比（电机转速 / 从动轴转速）",
        "efficiency of the reduction": "减速器效率",
        "inertia of the reduction at the motor shaft": "减速器转动惯量（折算到电机轴）",
        "rotor inertia": "转子转动惯量",
        "rated torque": "额定转矩",
        "peak torque rating": "允许峰值转矩",
        "driven shaft": "从动轴",
        "motor": "电机",
        "mean torque (N·m)": "平均转矩 (N·m)",
        "RMS torque (N·m)": "均方根转矩 (N·m)",
        "mean power (W)": "平均功率 (W)",
        "largest speed (rpm)": "最高转速 (rpm)",
        "motor torque with the flywheel (constant)": "装飞轮时的电机转矩（常数）",
        "largest motor speed": "电机最高转速",
        "mean motor power": "电机平均功率",
        "of it in rotor and reduction": "其中转子与减速器所占",
        "flywheel still to add on the motor shaft": "电机轴上尚需附加的飞轮",
        "Drive with the flywheel (ideal, energy method)": "装飞轮的驱动（理想飞轮，能量法）",
        "rigid drive": "刚性驱动",
        "with flywheel": "装飞轮",
        "RMS torque": "均方根转矩",
        "speed": "转速",
        "ok": "满足",
        "exceeded": "超出",
        "not checked": "未校核",
        "check": "校核",
        "limit": "限值",
        "result": "结果",
        "Motor check": "电机校核",
        "Verdict ({how}): {verdict}.": "结论（{how}）：{verdict}。",
        "adequate": "电机合格",
        "undersized": "电机偏小",
        "Four-quadrant torque–speed picture of the motor over the cycle, with the rated "
        "and peak torque envelopes.": "一个周期内电机的四象限转矩–转速图，及额定转矩与峰值转矩包络线。",
        "signs in the sense of motion of the driven shaft: the motor delivers power where "
        "torque and speed have one sign (motoring), takes it back where they differ "
        "(braking)": "符号以从动轴的运动方向为正：转矩与转速同号时电机输出功率（电动），异号时吸收功率（制动）",
        "reduction: T_M = T/(i·η) where the driven shaft takes power, T_M = T·η/i where it "
        "gives power back, plus (J_m + J_r)·i·α for the inertia of rotor and reduction": "减速器：从动轴吸收功率时 T_M = T/(i·η)，回馈功率时 T_M = T·η/i，另加转子与减速器的惯性转矩 (J_m + J_r)·i·α",
        "RMS ≤ rated torque: the cycle is short next to the motor's thermal time constant": "均方根转矩 ≤ 额定转矩：周期远短于电机的热时间常数",
        "with flywheel: the ideal flywheel of the energy method (δ): the motor gives the "
        "constant mean torque, the rotor and the reduction are part of the flywheel and its "
        "energy swing passes the reduction without loss; start-up is not checked": "装飞轮：按能量法的理想飞轮（δ）：电机输出恒定的平均转矩，转子与减速器计入飞轮，飞轮的能量波动经减速器时不计损失；不校核起动过程",
    }
)
# -- the textbook's terms (issue 37, items 9 and 12): Assur groups by class, the balancing
# torque, total reactions, the crank angle between the limit positions, load events by
# the position in the stroke
ZH.update(
    {
        "{letters} dyad (class {c}) {links}": "{letters} 型{c}级杆组 {links}",
        "class {c} group of {n} links {links}": "{c}级杆组（{n} 个构件）{links}",
        "class of the mechanism: class {c}": "机构级别：{c}级机构",
        "output {name}: stroke {stroke} {unit}, time ratio K = {k}, crank angle between the "
        "limit positions θ = {theta}°; limit positions at φ = {a}° and {b}°": "输出 {name}：行程 {stroke} {unit}，行程速比系数 K = {k}，极位夹角 θ = {theta}°；极限位置 φ = {a}° 与 {b}°",
        "output {name}: swing {swing}°, time ratio K = {k}, crank angle between the limit "
        "positions θ = {theta}°; limit positions at φ = {a}° ({name} at {ta}°) and {b}° "
        "({name} at {tb}°)": "输出 {name}：摆角 {swing}°，行程速比系数 K = {k}，极位夹角 θ = {theta}°；极限位置 φ = {a}°（{name} 位于 {ta}°）与 {b}°（{name} 位于 {tb}°）",
        "event: {load} switches {switch} at φ = {angle}° ({where})": "事件：{load} 在 φ = {angle}° 处{switch}（{where}）",
        "{p} at a limit position along ({x}, {y})": "{p} 沿 ({x}, {y}) 方向处于极限位置",
        "{p} {s} {lu} from its highest position": "{p} 距其最高位置 {s} {lu}",
        "{p} {s} {lu} from its lowest position": "{p} 距其最低位置 {s} {lu}",
        "{p} {s} {lu} from its rightmost position": "{p} 距其最右位置 {s} {lu}",
        "{p} {s} {lu} from its leftmost position": "{p} 距其最左位置 {s} {lu}",
        "{p} {s} {lu} from its extreme position against ({x}, {y})": "{p} 距其逆 ({x}, {y}) 方向的极限位置 {s} {lu}",
        "balancing torque M_b": "平衡力矩 M_b",
        "balancing force F_b": "平衡力 F_b",
        "{effort} of {name}: mean {mean} {unit}, largest magnitude {peak} {unit}": "原动件 {name} 的{effort}：平均值 {mean} {unit}，绝对值最大 {peak} {unit}",
        "; with friction mean {m} (approximate {a}), largest magnitude {p}": "；计摩擦时平均值 {m}（近似解 {a}），绝对值最大 {p}",
        " (means over one cycle, integrated between the load events)": "（平均值为一个周期内的平均，在载荷切换点之间分段积分）",
        "Total reactions F_R of the joints without friction: force of link i on link j (N) and "
        "its magnitude; prismatic pairs also N (normal force) and M (couple, N·m)": "不计摩擦的运动副总反力 F_R：构件 i 对构件 j 的作用力（N）及其大小；移动副另有 N（法向力）与 M（力偶矩，N·m）",
        "Total reactions F_R of the joints with friction (consistent solution): force of link i "
        "on link j (N) and its magnitude": "计摩擦的运动副总反力 F_R（一致解）：构件 i 对构件 j 的作用力（N）及其大小",
        "Balancing torque M_b of each driver (balancing force F_b of a sliding driver) without "
        "friction, with the approximate and the consistent friction solution, efficiency, "
        "friction status (0 converged, 1 by homotopy, 2 self-locking, 3 a relative speed is "
        "zero), input power and friction loss (W)": "各原动件上的平衡力矩 M_b（移动原动件为平衡力 F_b）：不计摩擦、计摩擦近似解与一致解；效率、摩擦状态（0 收敛，1 同伦法，2 自锁，3 相对速度为零）、输入功率与摩擦损耗（W）",
        "Largest total reactions F_R of the joints": "运动副总反力 F_R 的最大值",
        "largest |F_R| without friction (N)": "不计摩擦 |F_R| 最大值（N）",
        "largest |F_R| with friction (N)": "计摩擦 |F_R| 最大值（N）",
        "Kinetostatic analysis by `kinetostatics` (exact positions, velocities and "
        "accelerations; d'Alembert inertia loads; Newton–Euler reactions; friction by the "
        "approximate and the consistent solution). Conventions: x right, y up, angles and "
        "moments counter-clockwise positive; the total reaction F_Rij of a joint is the force "
        "of link i on link j.": "由 `kinetostatics` 进行动态静力分析（精确的位置、速度与加速度；达朗贝尔惯性力；牛顿–欧拉法求运动副总反力；摩擦按近似解与一致解）。约定：x 向右，y 向上，角度与力矩以逆时针为正；运动副总反力 F_Rij 为构件 i 对构件 j 的作用力。",
        "{effort} of {driver} without friction, with the approximate and with the consistent "
        "friction solution.": "{driver} 的{effort}：不计摩擦、计摩擦近似解与一致解。",
        "Magnitudes of the total reactions F_R of the joints.": "运动副总反力 F_R 的大小。",
        "Position {pos}: the loads drawn to scale (total reactions F_R of link i on link j at "
        "the joints, inertia forces F_I and inertia couples M_I, weights G, the process load "
        "and the {effort}).": "位置 {pos}：按比例绘制的各力（各运动副处构件 i 对构件 j 的总反力 F_R、惯性力 F_I 与惯性力偶矩 M_I、重力 G、工作阻力与{effort}）。",
        "driving moment constant, equal to the cycle mean of {torque} (M_d = work per cycle / "
        "2π, the work integrated exactly over one cycle, piece by piece between the load "
        "events)": "驱动力矩为常数，等于{torque}的周期平均值（M_d = 每周期功 / 2π，每周期功在一个周期内以载荷切换点分段精确积分）",
        "ΔW_max exact: ΔW(φ) integrated over one cycle piece by piece between the load events, "
        "where M_b is smooth, its extremes at the load events or where M_d = M_b ({positions} "
        "positions only for the pictures)": "ΔW_max 精确计算：ΔW(φ) 在一个周期内以载荷切换点分段积分（各段内 M_b 光滑），其极值位于载荷切换点或 M_d = M_b 处（{positions} 个位置仅用于绘图）",
        "energy method, first order in δ: ω_m = (ω_max + ω_min)/2 and the speed variation "
        "taken by the flywheel alone (J_F) or by the flywheel plus the machine's cycle-mean "
        "equivalent inertia (J_F − J_e)": "能量法，取 δ 的一阶近似：ω_m = (ω_max + ω_min)/2，速度波动由飞轮单独承担（J_F），或由飞轮与机构的周期平均等效转动惯量共同承担（J_F − J_e）",
        "flywheel on the crank shaft; on the motor shaft J_F/i² (i: the reduction ratio; gear "
        "inertia neglected)": "飞轮装于曲柄轴；装于电机轴时为 J_F/i²（i 为传动比；忽略齿轮惯量）",
        " These chapters are at the positions assigned ({labels}); the results, curves and "
        "diagrams over the cycle cover all positions.": "以上各章仅含指定位置（{labels}）；全周期的计算结果、曲线与线图包含所有位置。",
        "largest |torque| (N·m)": "转矩绝对值最大值 (N·m)",
        "largest |power| (W)": "功率绝对值最大值 (W)",
        "means and RMS values over one cycle, integrated exactly between the load events; "
        "peaks: the largest values over the positions sampled in the cycle": "平均值与均方根值按一个周期在载荷切换点之间精确积分；峰值为一个周期内各采样位置上的最大值",
    }
)

# The members and quantities of the tables and pictures (outputs/labels.py: column_label),
# and the link numbers of the file (number:).
ZH.update(
    {
        "link {n}": "构件{n}",
        "point {p}": "{p}点",
        "angular position": "角位置",
        "angular velocity": "角速度",
        "angular acceleration": "角加速度",
        "coordinate": "坐标",
        "normal force": "法向力",
        "couple": "力偶矩",
        "friction effort": "摩擦力（矩）",
        "driving torque": "驱动力矩",
        "driving force": "驱动力",
        "efficiency": "效率",
        "driver angle": "原动件转角",
        "driver travel": "原动件转过角度",
        "driver stroke": "原动件位移",
        "time": "时间",
        "friction status": "摩擦状态",
        "friction iterations": "摩擦迭代次数",
        "input power": "输入功率",
        "friction loss": "摩擦损耗功率",
        " (with friction, approximate)": "（计摩擦，近似解）",
        "Links (numbers as in the file and the pictures)": "构件（编号同文件与图）",
        "F_Rij: link i on link j at the joint; F_I, M_I: inertia; G: weight": "F_Rij：构件 i 作用于构件 j 的运动副总反力；F_I、M_I：惯性力与惯性力偶矩；G：重力",
        "Rows of `results.csv` (the column CSV row) at the positions {labels}; values to 5 "
        "significant digits (0: below 1e-9 of the largest value of its unit in the table, "
        "round-off), column names as in the CSV; |v|, |a|, |F| are the magnitudes of the "
        "components before them. Wide tables are split into groups of columns, each repeating "
        "the position, its CSV row and its angle.": "下表为 `results.csv` 在位置 {labels} 的行（CSV row 列）；数值取 5 位有效数字（0 表示小于表中同单位最大值的 1e-9，即舍入误差）。列名为各量的名称与符号：θ、ω、α 的下标为构件编号（见第 1 节构件表），F_Rij 为构件 i 对构件 j 的反力；不带 x、y 的 v_B、a_B、F_Rij 为其前两个分量的合成大小。较宽的表格分为若干列组，每组重复位置、CSV 行号与位置角。",
    }
)

# issue 37, the rendering: the energy diagram names its two extremes and the swing apart
ZH.update(
    {
        "E_{word}: ΔW = {w} J (φ = {phi}°)": "E_{word}：ΔW = {w} J（φ = {phi}°）",
        "maximum energy swing ΔW_max = E_max − E_min = {s} J": "最大盈亏功 ΔW_max = E_max − E_min = {s} J",
        "page {n}/{nb}": "第 {n} 页，共 {nb} 页",
        "{effort} of {driver} (no joint has friction).": "{driver} 的{effort}（各运动副均不计摩擦）。",
        "Balancing torque M_b of each driver (balancing force F_b of a sliding driver) "
        "and the input power (W); no joint has friction": "各原动件上的平衡力矩 M_b（移动原动件为平衡力 F_b）与输入功率（W）；各运动副均不计摩擦",
    }
)

# the graded methods' texts (issue 38) are kept in their own module
ZH.update(_METHODS)
ZH.update(_SIZING)
