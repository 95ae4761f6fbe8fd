"""Compare committed oracle data with freshly regenerated data.

Usage: python compare.py COMMITTED_DIR REGENERATED_DIR

Same set of files, same structure, same strings/booleans/nulls, and every number equal to a relative
tolerance of 1e-12 (absolute floor 1e-14: see ABS and REL); numbers written inside strings (an expression
driver's text) are compared the same way, the rest of the string exactly. Prints a summary of the differences and exits 1 when the
committed data are stale; prints "oracle data up to date (N files, M cases)" and exits 0 otherwise.
"""

import glob
import json
import os
import re
import sys

# Relative: numbers computed through a dense solve (a spline's knot derivatives) carry its
# roundoff, whose last bits follow numpy's LAPACK/SIMD kernels on the machine: on the machine of
# 2026-12-06 one value of 5955 cases (a cam pair's gamma on a closed spline) came out 1.4e-13
# relative from the committed data with the pinned versions. A stale generator changes numbers
# far more than this.
REL = 1e-12
# Values that cancel to zero (Φ and its derivatives at a solution: "at-solution" cases) are
# roundoff of O(1) terms, and their last bits follow the platform's libm and numpy's SIMD kernels
# (a new machine gave differences of up to 1.8e-15 there). Below this absolute size two numbers
# are the same value; it is 50 ulps of 1, far below anything the gate checks.
ABS = 1e-14
SHOW = 40  # differences listed in full; the rest are counted


def close(a, b):
    return abs(a - b) <= max(ABS, REL * max(abs(a), abs(b)))


# A decimal number inside a string (an expression's constants: "1.6199224177729643",
# "2.4416350910826137", "1e-3"). Constants computed at generation time carry the same last-bit
# platform differences as the numbers beside them (a new machine gave ...643 against ...645).
NUMBER = re.compile(r"(\d+\.\d*(?:[eE][-+]?\d+)?|\.\d+(?:[eE][-+]?\d+)?|\d+[eE][-+]?\d+|\d+)")


def same_text(a, b):
    """Equal strings, up to numbers inside them that are `close`."""
    if a == b:
        return True
    pa, pb = NUMBER.split(a), NUMBER.split(b)
    if len(pa) != len(pb):
        return False
    # re.split with one group: text at even positions, numbers at odd ones.
    for i, (x, y) in enumerate(zip(pa, pb)):
        if i % 2 == 0 and x != y:
            return False
        if i % 2 == 1 and not close(float(x), float(y)):
            return False
    return True


def is_num(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def walk(old, new, where, out):
    """Append (where, committed, regenerated) for each difference."""
    if is_num(old) and is_num(new):
        if not close(float(old), float(new)):
            out.append((where, old, new))
        return
    if type(old) is not type(new):
        out.append((where, _short(old), _short(new)))
        return
    if isinstance(old, dict):
        for k in old:
            if k not in new:
                out.append((f"{where}.{k}", "present", "missing"))
            else:
                walk(old[k], new[k], f"{where}.{k}" if where else k, out)
        for k in new:
            if k not in old:
                out.append((f"{where}.{k}", "missing", "present"))
        return
    if isinstance(old, list):
        if len(old) != len(new):
            out.append((f"{where} (length)", len(old), len(new)))
            return
        for n, (a, b) in enumerate(zip(old, new)):
            walk(a, b, f"{where}[{n}]", out)
        return
    if isinstance(old, str) and same_text(old, new):
        return
    if old != new:
        out.append((where, old, new))


def _short(x):
    s = json.dumps(x)
    return s if len(s) <= 60 else s[:57] + "..."


def compare_file(old, new):
    """Differences of one element file, cases matched by position and named by label."""
    out = []
    top_old = {k: v for k, v in old.items() if k != "cases"}
    top_new = {k: v for k, v in new.items() if k != "cases"}
    walk(top_old, top_new, "", out)
    co, cn = old.get("cases", []), new.get("cases", [])
    if len(co) != len(cn):
        out.append(("cases (count)", len(co), len(cn)))
    for a, b in zip(co, cn):
        label = a.get("label", "?")
        if a.get("label") != b.get("label"):
            out.append((f"case {label!r}: label", a.get("label"), b.get("label")))
            continue
        diffs = []
        walk(a, b, "", diffs)
        out += [(f"case {label!r}: {w}", x, y) for w, x, y in diffs]
    return out


def main(argv):
    if len(argv) != 3:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    old_dir, new_dir = argv[1], argv[2]
    old_files = {os.path.basename(p) for p in glob.glob(os.path.join(old_dir, "*.json"))}
    new_files = {os.path.basename(p) for p in glob.glob(os.path.join(new_dir, "*.json"))}
    problems = []  # (file, where, committed, regenerated)
    for f in sorted(old_files - new_files):
        problems.append((f, "file", "committed", "not generated any more"))
    for f in sorted(new_files - old_files):
        problems.append((f, "file", "missing from oracle/data", "generated"))
    n_cases = 0
    per_file = {}
    for f in sorted(old_files & new_files):
        with open(os.path.join(old_dir, f), encoding="utf-8") as fh:
            try:
                old = json.load(fh)
            except json.JSONDecodeError as e:
                problems.append((f, "file", f"invalid JSON ({e})", "valid"))
                continue
        with open(os.path.join(new_dir, f), encoding="utf-8") as fh:
            new = json.load(fh)
        n_cases += len(new.get("cases", []))
        diffs = compare_file(old, new)
        if diffs:
            per_file[f] = len(diffs)
        problems += [(f, w, x, y) for w, x, y in diffs]
    if not problems:
        print(f"oracle data up to date ({len(new_files)} files, {n_cases} cases)")
        return 0
    print(f"oracle data are STALE: {len(problems)} difference(s) between oracle/data/ (committed) "
          f"and a fresh regeneration (numbers compared at relative {REL:g}):")
    for f, w, x, y in problems[:SHOW]:
        print(f"  {f}: {w}: committed {x!r}, regenerated {y!r}")
    if len(problems) > SHOW:
        print(f"  ... and {len(problems) - SHOW} more")
    if per_file:
        print("differences per file: " + ", ".join(f"{f} {n}" for f, n in sorted(per_file.items())))
    print("If the change is intended, run `cargo xtask oracle` and commit oracle/data/.")
    return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
