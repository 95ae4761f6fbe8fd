"""Regenerate every oracle reference file.

Usage: python generate.py OUTDIR      (cargo xtask oracle runs it with OUTDIR = oracle/data)

Removes stale *.json files of OUTDIR first, so a removed element disappears from the data too.
"""

import glob
import os
import sys
import time

import gen_drivers
import gen_joints
import gen_primitives

GENERATORS = (gen_primitives, gen_joints, gen_drivers)


def main(argv):
    if len(argv) != 2:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    outdir = argv[1]
    os.makedirs(outdir, exist_ok=True)
    for old in glob.glob(os.path.join(outdir, "*.json")):
        os.remove(old)
    start = time.time()
    total_files = total_cases = 0
    for gen in GENERATORS:
        for element, n in gen.main(outdir).items():
            total_files += 1
            total_cases += n
    print(f"oracle: wrote {total_files} files, {total_cases} cases to {outdir} "
          f"in {time.time() - start:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
