"""The page's words in English and Chinese (``api/texts``).

Each English text is looked up in the report's and pictures' Chinese (:mod:`kinetostatics.
outputs.zh`, through :func:`~kinetostatics.outputs.lang.tr`) first; the words only the
editor uses have their Chinese here.
"""

from __future__ import annotations

from ..outputs.lang import tr
from ..outputs.zh import ZH

__all__ = ["UI", "page_texts"]

# key -> (English, Chinese where the report has none)
UI: dict[str, tuple[str, str]] = {
    "title": ("kinetostatics editor", "kinetostatics 编辑器"),
    "save": ("Save", "保存"),
    "saved": ("saved", "已保存"),
    "unsaved": ("unsaved changes", "有未保存的修改"),
    "reloaded": ("reloaded: the file changed on disk", "已重新载入：磁盘上的文件已修改"),
    "changed": ("the file changed on disk", "磁盘上的文件已修改"),
    "reload": ("Reload", "重新载入"),
    "keep": ("Keep mine", "保留我的"),
    "analysing": ("analysing…", "分析中…"),
    "problems": ("problems", "问题"),
    "no_problems": ("no problems", "没有问题"),
    "angle": ("crank angle", "曲柄转角"),
    "play": ("Play", "播放"),
    "pause": ("Pause", "暂停"),
    "forces": ("forces", "力"),
    "friction": ("with friction", "计摩擦"),
    "friction_circles": ("friction circles", "摩擦圆"),
    "paths": ("paths", "轨迹"),
    "sketch": ("sketch", "草图"),
    "force_scale": ("force scale", "力比例尺"),
    "length_scale": ("length scale", "长度比例尺"),
    "torque": ("driving effort", "驱动力矩"),
    "reaction": ("reaction", "反力"),
    "output": ("output", "输出"),
    "checks": ("self-checks", "自检"),
    "warnings": ("warnings", "警告"),
    "download": ("Download", "下载"),
    "language": ("language", "语言"),
    "without friction": ("without friction", "不计摩擦"),
    "with friction, consistent": ("with friction, consistent", "计摩擦，一致解"),
    "keys_here": ("keys here", "此处可用的键"),
    "stale": ("the drawing is of the last good text", "图为上一次无误文本的结果"),
    "sketch_far": ("sketched point far from where it assembled", "草图点与装配位置相距较远"),
    "seconds": ("analysed in {s} s", "分析用时 {s} 秒"),
    "legend": ("F_Rij: link i on link j at the joint; F_I, M_I: inertia; G: weight", ""),
}


def page_texts() -> dict[str, dict[str, str]]:
    """``{"en": {key: text}, "zh": {key: text}}``: the report's Chinese where it has the
    English text, else the editor's own."""
    zh = {k: (tr(en, "zh") if en in ZH else own) for k, (en, own) in UI.items()}
    return {"en": {k: en for k, (en, _) in UI.items()}, "zh": zh}
