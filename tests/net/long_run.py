"""Long run of the verification net: every relation on N generated mechanisms.

    PYTHONPATH=src python tests/net/long_run.py --mechanisms 10000 --write

Mechanism k (seed k) is generated and put through every relation of
``relations.RELATIONS`` (the energy check on one mechanism in ``--energy-every``,
it integrates the motion).  Work is spread over ``--workers`` processes; a
progress line is printed.  Each mechanism's outcome is appended as one JSON line
to ``--results`` (default ``tests/net/long_run/features.jsonl``, with the commit it
ran at, the mechanism's features and its time; ``results.jsonl`` holds the run of the
generator before it had features), so an interrupted run resumes where it stopped:
seeds already in the file are not run again (``--fresh`` starts over).  The counts (mechanisms
generated, candidates rejected, relations checked / failed / not applicable, the
largest discrepancy per relation and the failing seeds), taken over every seed of
the requested range found in the file, are printed, and with ``--write`` replace
the block between the markers in docs/verification.md; ``--report`` only does
that, computing nothing.
"""

from __future__ import annotations

import argparse
import json
import math
import multiprocessing as mp
import os
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
RESULTS = HERE / "long_run" / "features.jsonl"  # results.jsonl: the run before the features
BEGIN = "<!-- long-run:begin -->"
END = "<!-- long-run:end -->"


def _setup():
    sys.path[:0] = [str(ROOT / "src"), str(HERE)]


def check_one(args):
    seed, energy = args
    _setup()
    import generate as G
    import relations as R

    out = {"seed": seed, "results": {}}
    t0 = time.time()
    try:
        doc = G.generate(seed)
        out["rejected"] = G.rejections(seed)
        out["features"] = sorted(G.features(doc))
    except Exception as exc:  # noqa: BLE001
        out["error"] = f"{type(exc).__name__}: {exc}"[:200]
        return out
    for name, rel in R.RELATIONS.items():
        if name == "energy" and not energy:
            continue
        R.WORST[:] = [0.0, ""]
        try:
            v = rel(doc, seed)
            col = R.WORST[1]
        except Exception as exc:  # noqa: BLE001
            v, col = math.inf, f"{type(exc).__name__}: {str(exc)[:120]}"
        hint = None
        if v is not None and not v <= R.TOLERANCE[name]:
            hint = R.diagnose(name, doc, seed)
        failed = v is not None and not v <= R.TOLERANCE[name]
        out["results"][name] = (
            [v, (col if hint is None else f"{col} [{hint}]")[:160]] if failed else v
        )
    out["seconds"] = round(time.time() - t0, 2)
    return out


def _commit() -> str:
    try:
        return subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"],
            cwd=ROOT,
            text=True,
            capture_output=True,
            check=True,
        ).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def _load(path: Path) -> dict[int, dict]:
    """The outcomes already in the results file, by seed (a cut last line is dropped)."""
    done = {}
    if path.exists():
        for line in path.read_text(encoding="utf-8").splitlines():
            try:
                out = json.loads(line)
            except ValueError:
                continue
            done[out["seed"]] = out
    return done


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mechanisms", type=int, default=200)
    ap.add_argument("--first-seed", type=int, default=1_000_000)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--energy-every", type=int, default=20)
    ap.add_argument("--results", type=Path, default=RESULTS)
    ap.add_argument("--fresh", action="store_true", help="forget the results file")
    ap.add_argument("--report", action="store_true", help="only report what the file holds")
    ap.add_argument("--write", action="store_true", help="update docs/verification.md")
    a = ap.parse_args(argv)
    _setup()
    import relations as R

    seeds = range(a.first_seed, a.first_seed + a.mechanisms)
    a.results.parent.mkdir(parents=True, exist_ok=True)
    if a.fresh and a.results.exists():
        a.results.unlink()
    done = _load(a.results)
    jobs = [(s, (s - a.first_seed) % a.energy_every == 0) for s in seeds if s not in done]
    commit = _commit()
    t0 = time.time()
    if jobs and not a.report:
        print(f"{len(done)} mechanisms already in {a.results.name}; {len(jobs)} to run")
        with mp.Pool(a.workers) as pool, a.results.open("a", encoding="utf-8") as f:
            for k, out in enumerate(pool.imap_unordered(check_one, jobs, chunksize=4), 1):
                out["commit"] = commit
                f.write(json.dumps(out) + "\n")
                f.flush()
                done[out["seed"]] = out
                if k % 10 == 0 or k == len(jobs):
                    os.fsync(f.fileno())
                    el = time.time() - t0
                    print(f"\r{k}/{len(jobs)} mechanisms, {el:.0f} s", end="", flush=True)
        print()
    block = _block(a, R, [done[s] for s in seeds if s in done])
    print(block)
    if a.write:
        write_block(block, BEGIN, END)
    return 0


def write_block(block: str, begin: str, end: str) -> None:
    """Replace the part of docs/verification.md from ``begin`` to ``end`` (the markers
    included: ``block`` carries them) with ``block``."""
    doc = ROOT / "docs" / "verification.md"
    text = doc.read_text(encoding="utf-8")
    i, j = text.index(begin), text.index(end) + len(end)
    doc.write_text(text[:i] + block + text[j:], encoding="utf-8")


def _block(a, R, outs: list[dict]) -> str:
    stats = {n: {"checked": 0, "failed": 0, "na": 0, "max": 0.0, "seeds": []} for n in R.RELATIONS}
    generated = rejected = errors = 0
    seconds = 0.0
    featured = {}
    commits = sorted({out.get("commit", "unknown") for out in outs})
    for out in outs:
        if "error" in out:
            errors += 1
            continue
        generated += 1
        rejected += out["rejected"]
        seconds += out.get("seconds", 0.0)
        for f in out.get("features", []) + (["any"] if out.get("features") else []):
            featured[f] = featured.get(f, 0) + 1
        for name, res in out["results"].items():
            s = stats[name]
            v, col = res if isinstance(res, list) else (res, "")
            if v is None:
                s["na"] += 1
                continue
            s["checked"] += 1
            if v > R.TOLERANCE[name] or not math.isfinite(v):
                s["failed"] += 1
                s["seeds"].append((out["seed"], v, col))
            elif v > s["max"]:
                s["max"] = v
    lines = [
        BEGIN,
        "",
        f"Last long run: `python tests/net/long_run.py --mechanisms {a.mechanisms}` "
        f"(seeds {a.first_seed}…{a.first_seed + a.mechanisms - 1}; "
        f"{len(outs)} of {a.mechanisms} done, at commit{'s' * (len(commits) > 1)} "
        f"{', '.join(commits)}).",
        "",
        f"- mechanisms generated: {generated}; candidates rejected on the way: {rejected}; "
        f"seeds without an acceptable mechanism: {errors}",
        f"- time: {seconds / 3600:.2f} h in the workers (generation and relations, "
        f"{seconds / max(generated, 1):.1f} s per mechanism)",
        "- mechanisms with each feature (generate.FEATURES): "
        + (
            ", ".join(f"{k} {v}" for k, v in sorted(featured.items()) if k != "any")
            + f"; with at least one: {featured.get('any', 0)}"
            if featured
            else "not recorded"
        ),
        "",
        "| relation | checked | not applicable | failed "
        "| largest discrepancy among the passing | tolerance |",
        "|---|---|---|---|---|---|",
    ]
    for name, s in stats.items():
        lines.append(
            f"| {name} | {s['checked']} | {s['na']} | {s['failed']} | "
            f"{s['max']:.2g} | {R.TOLERANCE[name]:g} |"
        )
    fails = [(n, seed, v, col) for n, s in stats.items() for seed, v, col in s["seeds"]]
    lines += [
        "",
        "Failures (relation, seed, discrepancy, worst column or error [hint]):"
        if fails
        else "Failures: none.",
        "",
    ]
    for n, seed, v, col in fails[:60]:
        lines.append(f"- {n}, seed {seed}: {v:.3g} — {col}")
    if len(fails) > 60:
        lines.append(f"- … and {len(fails) - 60} more")
    lines += ["", END]
    return "\n".join(lines)


if __name__ == "__main__":
    raise SystemExit(main())
