"""Extreme scales, speeds and mass ratios of the slider-crank against the closed form.

The cases and the error measures are those of tests/kinematics/test_scales.py (which
asserts them): each case analysed over a full cycle (360 positions) by the
closed-form fast path and by the general Newton path.  A second table gives the
largest condition number of the RRP dyad over the cycle when every length of
the micro slider-crank is multiplied by a factor (the mechanism is the same up
to scale).

    python tests/benchmarks/accuracy_scales.py [--update]
"""

from __future__ import annotations

import warnings

import accuracy_common as ac
import numpy as np
from accuracy_common import Table, e

import kinetostatics as ks
from tests.kinematics import test_scales as ts

FACTORS = ("100", "10", "1", "0.1", "0.01")


def build(timing: bool = True):
    tab = Table(
        [
            "case",
            "L_ref (m)",
            "speed (rpm)",
            "path",
            "pose",
            "q̇",
            "q̈",
            "reactions",
            "torque",
            "friction torque (eq. 9)",
            "worst",
        ]
    )
    worst = (0.0, "")
    for case in ts.CASES:
        model = ts.model(case)
        l_ref = ks.build_system(model).l_ref
        rpm = model.drivers[0].motion.speed * 60 / (2 * np.pi)
        for general in (False, True):
            err = ts.errors(model, general)
            tab.add(
                case,
                f"{l_ref:.3g}",
                f"{rpm:g}",
                "Newton" if general else "fast",
                *(e(v) for v in vars(err).values()),
                e(err.worst),
            )
            if err.worst > worst[0]:
                worst = (err.worst, f"{case}, {'Newton' if general else 'fast'} path")
    text = (
        tab.markdown()
        + f"\n\nWorst relative error over all cases: **{worst[0]:.1e}** ({worst[1]})."
    )
    cond = Table(
        [
            "length × factor",
            "rod (m)",
            "max condition number over the cycle",
            "NearSingularWarning",
            "result",
        ]
    )
    for f in FACTORS:
        model = ts._micro(f)
        rod = 350e-6 * float(f)
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            try:
                r = ks.analyze(model)
                c, out = f"{np.max(r['rod_slider.cond']):.2e}", e(ts.errors(model).worst)
                out = f"worst error {out}"
            except ks.ModelError as ex:
                c, out = "—", "ModelError: " + str(ex).split(": ", 2)[-1].split(";")[0]
        warned = any(issubclass(x.category, ks.NearSingularWarning) for x in w)
        cond.add(f, f"{rod:.3g}", c, "yes" if warned else "no", out)
    return {"scales": text, "scales-condition": cond.markdown()}, None


if __name__ == "__main__":
    ac.main(build)
