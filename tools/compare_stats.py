#!/usr/bin/env python3
"""Whether two silt binaries give the same stats on the same scenes, column by column.

    tools/compare_stats.py OLD_SILT NEW_SILT [--scenes DIR] [--fixed-dt]

Runs each dry scene of DIR (default: scenes/) with both binaries on 1 and 2 threads, with the
run lengths below, and prints, per scene and thread count, the columns that are bitwise equal,
those that differ, and the largest relative difference among them. Scenes given in units of a
contact time (run.dt_over_tc) whose step differs between the two can also be run at OLD's
absolute step (--fixed-dt), so that a change of the contact-time constant does not hide the trajectories.
Used to check that a refactoring keeps the trajectories to the last bit (README, "Engine seams").
"""
import argparse
import csv
import json
import os
import re
import subprocess
import sys
import tempfile

# scene: extra arguments (run lengths that take seconds, not minutes)
RUNS = {
    "collision_normal": [],
    "bounce_dry": [],
    "chute": ["--steps", "3000", "--every", "100"],
    "pack_2d": ["--steps", "20000", "--every", "1000"],
    "shear2d_dry": ["--steps", "20000", "--every", "500"],
    "silo": ["--steps", "20000", "--every", "1000"],
    "shear3d_frictionless": ["--steps", "3000", "--every", "100"],
}


def run(binary, scene, args, threads, out):
    cmd = [binary, "run", scene, *args, "--threads", str(threads), "--quiet", "--stats", out]
    r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed ({r.returncode}): {r.stderr.strip()}")


def compare(old_csv, new_csv):
    a = list(csv.reader(open(old_csv)))
    b = list(csv.reader(open(new_csv)))
    if a[0] != b[0] or len(a) != len(b):
        return None
    same, differ, worst = [], [], 0.0
    for c, name in enumerate(a[0]):
        va = [r[c] for r in a[1:]]
        vb = [r[c] for r in b[1:]]
        if va == vb:
            same.append(name)
            continue
        differ.append(name)
        for x, y in zip(map(float, va), map(float, vb)):
            worst = max(worst, abs(x - y) / max(abs(x), abs(y), 1e-300))
    return len(a) - 1, same, differ, worst


def step_of(binary, scene, tmp):
    summary = os.path.join(tmp, "dt.json")
    subprocess.run([binary, "run", scene, "--steps", "1", "--quiet", "--summary", summary],
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
    return json.load(open(summary))["dt"]


def fixed_dt_scene(old, new, scene, tmp):
    """A copy of the scene with run.dt_over_tc replaced by OLD's absolute step, if NEW's differs."""
    dt = step_of(old, scene, tmp)
    if step_of(new, scene, tmp) == dt:
        return None
    text = open(scene).read()
    fixed, n = re.subn(r"(?m)^dt_over_tc\s*=.*$", f"dt = {dt!r}", text)
    if n != 1:
        return None
    path = os.path.join(tmp, os.path.basename(scene).replace(".toml", "_fixed_dt.toml"))
    open(path, "w").write(fixed)
    return path


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("old")
    p.add_argument("new")
    p.add_argument("--scenes", default=os.path.join(os.path.dirname(__file__), "..", "scenes"))
    p.add_argument("--fixed-dt", action="store_true", help="also run scenes in contact times at OLD's absolute step")
    a = p.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        cases = []
        for name, args in RUNS.items():
            scene = os.path.join(a.scenes, name + ".toml")
            if not os.path.exists(scene):
                print(f"{name}: not in {a.scenes}, skipped")
                continue
            cases.append((name, scene, args))
            if a.fixed_dt and "dt_over_tc" in open(scene).read():
                fixed = fixed_dt_scene(a.old, a.new, scene, tmp)
                if fixed:
                    cases.append((name + " (OLD's dt)", fixed, args))
        for name, scene, args in cases:
            for threads in (1, 2):
                o = os.path.join(tmp, "old.csv")
                n = os.path.join(tmp, "new.csv")
                run(a.old, scene, args, threads, o)
                run(a.new, scene, args, threads, n)
                r = compare(o, n)
                if r is None:
                    print(f"{name}, {threads} thread(s): different columns or rows")
                    continue
                rows, same, differ, worst = r
                print(f"{name}, {threads} thread(s), {rows} rows: bitwise {', '.join(same)}; "
                      f"differ {', '.join(differ) or '-'}" + (f" (at most {worst:.2g} relative)" if differ else ""))


if __name__ == "__main__":
    main()
