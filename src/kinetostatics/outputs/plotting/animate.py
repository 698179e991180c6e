"""Animation of the mechanism over the rows (GIF through Pillow, MP4 with ffmpeg)."""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

import numpy as np

from ...base.files import write_whole
from .draw import _draw_moving, _draw_static, _drawing_sheet, _l_ref, _loads_at, _sheet_title
from .rows import _position_title, _sorted
from .style import PictureError, _fit_sheet, _inside_axes, _rc


# -- animation ---------------------------------------------------------------------
def animate(  # noqa: PLR0913  the public keywords (docs/pictures.md)
    result,
    path: str | Path,
    *,
    forces: bool = False,
    friction: bool = False,
    paths: Iterable[str] = (),
    fps: float = 20.0,
    dpi: float = 110.0,
    max_size_mm=(160.0, 120.0),
    lang: str = "en",
) -> Path:
    """Write an animation of the mechanism over the result's rows (one frame per row,
    in order of travel): ``.gif`` through Pillow, ``.mp4`` only if ffmpeg is on the
    PATH.  ``forces`` overlays the loads at one force scale for the whole cycle.
    Returns the path written.
    """
    import shutil

    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in (".gif", ".mp4"):
        raise PictureError(
            f"{path}: an animation is written as .gif (or .mp4 with ffmpeg), "
            f"not '{suffix or 'no suffix'}'"
        )
    ffmpeg = shutil.which("ffmpeg") if suffix == ".mp4" else None
    if suffix == ".mp4" and ffmpeg is None:
        raise PictureError(f"{path}: writing MP4 needs ffmpeg on the PATH; write a .gif instead")

    path.parent.mkdir(parents=True, exist_ok=True)
    write_whole(
        path,
        lambda tmp: _write(
            result, tmp, path, ffmpeg, forces, friction, paths, fps, dpi, max_size_mm, lang
        ),
    )
    return path


def _write(result, tmp, path, ffmpeg, forces, friction, paths, fps, dpi, max_size_mm, lang):  # noqa: PLR0913  animate's keywords, passed on
    """The frames of :func:`animate` written to ``tmp`` (``path`` names it in messages):
    MP4 through ``ffmpeg`` when given, else GIF."""
    import subprocess

    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.text import Text

    _, order, _ = _sorted(result)
    with _rc(lang):
        loads = {}
        if forces:
            loads = {int(k): _loads_at(result, int(k), friction=friction) for k in order}
        scene, paper, fig, ax, mu_f = _drawing_sheet(
            result, paths, max_size_mm, dpi, forces, [a for arr in loads.values() for a in arr]
        )
        ax.set_title(
            _sheet_title(result, scene, paper, mu_f, None, friction, lang),
            loc="left",
            fontsize=8.5,
        )
        static = _draw_static(ax, scene, paper, lang)
        _inside_axes(fig, ax, [a for a in static if isinstance(a, Text)])
        _fit_sheet(fig, ax)
        canvas = FigureCanvasAgg(fig)
        canvas.draw()
        background = canvas.copy_from_bbox(fig.bbox)
        w, h = canvas.get_width_height()
        frames = []
        proc = None
        if ffmpeg:
            proc = subprocess.Popen(
                [
                    ffmpeg,
                    "-y",
                    "-loglevel",
                    "error",
                    "-f",
                    "rawvideo",
                    "-pix_fmt",
                    "rgba",
                    "-s",
                    f"{w}x{h}",
                    "-r",
                    f"{fps:g}",
                    "-i",
                    "-",
                    "-pix_fmt",
                    "yuv420p",
                    "-vf",
                    "pad=ceil(iw/2)*2:ceil(ih/2)*2",
                    "-f",
                    "mp4",
                    str(tmp),
                ],
                stdin=subprocess.PIPE,
            )
        from PIL import Image

        palette = None
        for k in order:
            k = int(k)
            canvas.restore_region(background)
            geo = scene.geometry(k)
            arts = _draw_moving(
                ax,
                scene,
                geo,
                paper,
                labels=True,
                forces=loads.get(k),
                mu_f=mu_f,
                l_ref=_l_ref(scene),
            )
            t = ax.text(
                0.99,
                0.99,
                _position_title(result, k, lang),
                ha="right",
                va="top",
                fontsize=8,
                transform=ax.transAxes,
                zorder=11,
            )
            arts.append(t)
            for a in arts:
                ax.draw_artist(a)
            buf = np.asarray(canvas.buffer_rgba())
            if proc is not None:
                proc.stdin.write(buf.tobytes())
            else:
                img = Image.fromarray(buf[..., :3].copy())
                if palette is None:
                    palette = img.quantize(colors=128, method=Image.Quantize.MEDIANCUT)
                frames.append(img.quantize(palette=palette, dither=Image.Dither.NONE))
            for a in arts:
                a.remove()
    if proc is not None:
        proc.stdin.close()
        if proc.wait() != 0:
            raise PictureError(f"{path}: ffmpeg failed (exit {proc.returncode})")
        return
    frames[0].save(
        tmp,
        format="GIF",
        save_all=True,
        append_images=frames[1:],
        duration=int(round(1000 / fps)),
        loop=0,
        optimize=False,
        disposal=1,
    )
