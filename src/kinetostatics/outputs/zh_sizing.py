# ruff: noqa: E501  (the Chinese texts of the translation table are long lines)
"""The Chinese texts of the sizing chapter (issue 41: the bearings, the pins, the links'
sections; outputs/report/sizing.py), keyed by their English text; :mod:`.zh` adds them to
its table (looked up by :func:`.lang.tr`)."""

from __future__ import annotations

ZH: dict[str, str] = {
    "{n}. Sizing: bearings, pins and links": "{n}. 零件尺寸校核：轴承、销轴与构件",
    "From the reactions of the frictionless solution over the cycle: the peaks are "
    "the largest over the analysed positions and the points between them where the "
    "cycle's integral samples the motion; the means and the bearing life are exact "
    "integrals over the cycle. Stresses in MPa.": "依据一个运动循环中不计摩擦时的运动副反力：峰值取自各计算位置及其间循环积分的采样点，平均值与轴承寿命为全循环的精确积分。应力单位为 MPa。",
    "rolling bearings (ISO 281): P = (∫|F|^p·|ω_rel|dt / ∫|ω_rel|dt)^(1/p), p = 3 (ball), "
    "10/3 (roller); L10 = (C/P)^p·10⁶ rev; L10h = L10/(3600·n), n = ∫|ω_rel|dt/(2π·T); an "
    "oscillating joint turns 2φ per cycle for a swing φ (the equivalent-speed rule)": "滚动轴承（ISO 281）：P = (∫|F|^p·|ω_rel|dt / ∫|ω_rel|dt)^(1/p)，球轴承 p = 3，滚子轴承 p = 10/3；L10 = (C/P)^p·10⁶ 转；L10h = L10/(3600·n)，n = ∫|ω_rel|dt/(2π·T)；往复摆动的转动副每循环转过 2φ（φ 为摆角，即当量转速法）",
    "plain bearings: p = |F|/(d·b), v = |ω_rel|·d/2, pv": "滑动轴承：p = |F|/(d·b)，v = |ω_rel|·d/2，pv 值",
    "pins: τ = |F|/(k·πd²/4) for k shear planes; the eyes' pressure |F|/(d·w)": "销轴：k 个剪切面时 τ = |F|/(k·πd²/4)；销孔挤压应力 |F|/(d·w)",
    "links: N, V, M along the axis from the first pin, the inertia distributed along a "
    "uniform link, lumped at the centre of mass of another; σ = |N|/A + |M|/Z": "构件：自第一个铰链沿轴线的轴力 N、剪力 V、弯矩 M；均质构件的惯性力沿轴线分布，其余构件集中于质心；σ = |N|/A + |M|/Z",
    "fatigue at the critical section: Goodman 1/n = σ_a/S_e + σ_m/S_ut, Soderberg "
    "1/n = σ_a/S_e + σ_m/S_y (n = S_e/σ_a for a compressive mean); yield n = S_y/σ": "危险截面的疲劳强度：Goodman 1/n = σ_a/S_e + σ_m/S_ut，Soderberg 1/n = σ_a/S_e + σ_m/S_y（平均应力为压应力时 n = S_e/σ_a）；屈服 n = S_y/σ",
    "Rolling bearings: equivalent load and rating life": "滚动轴承：当量动载荷与额定寿命",
    "Plain bearings: pressure, sliding speed and pv": "滑动轴承：压强、滑动速度与 pv 值",
    "Pins: shear stress and bearing pressure": "销轴：剪切应力与挤压应力",
    "Links: peaks over the cycle and safety factors": "构件：循环内峰值与安全系数",
    "ball bearing": "球轴承",
    "roller bearing": "滚子轴承",
    "peak |F| (N)": "|F| 峰值 (N)",
    "motion": "运动形式",
    "rotating": "整周转动",
    "peak p (MPa)": "p 峰值 (MPa)",
    "mean p (MPa)": "p 平均值 (MPa)",
    "peak v (m/s)": "v 峰值 (m/s)",
    "peak pv (MPa·m/s)": "pv 峰值 (MPa·m/s)",
    "shear planes": "剪切面数",
    "peak τ (MPa)": "τ 峰值 (MPa)",
    "peak pressure on the eyes (MPa)": "销孔挤压应力峰值 (MPa)",
    "section": "截面",
    "rectangle": "矩形",
    "circle": "圆形",
    "tube": "圆管",
    "I": "工字形",
    "at (mm)": "位置 (mm)",
    "n yield": "n 屈服",
    "axial force N (kN)": "轴力 N (kN)",
    "bending moment M (N·m)": "弯矩 M (N·m)",
    "station from the first pin (mm)": "距第一个铰链的距离 (mm)",
    "Axial force and bending moment along the links: their range over the "
    "cycle at each station; dashed: the critical section": "沿构件轴线的轴力与弯矩：各截面在一个循环内的变化范围；虚线为危险截面",
    "Warnings:": "警告：",
}
