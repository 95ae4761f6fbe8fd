"""Regenerate every oracle reference file.

Usage: python generate.py OUTDIR      (cargo xtask oracle runs it with OUTDIR = oracle/data)

Removes stale *.json files of OUTDIR first, so a removed element disappears from the data too.
Elements are generated in parallel processes; each has its own fixed seed, so the output does not
depend on the order or the number of processes.
"""

import glob
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor

import common
import gen_couplers
import gen_curves
import gen_drivers
import gen_expressions
import gen_joints
import gen_limits
import gen_pose
import gen_primitives
import gen_surfaces

GENERATORS = {
    m.__name__: m for m in (gen_primitives, gen_joints, gen_drivers, gen_pose, gen_couplers,
                               gen_limits, gen_curves, gen_surfaces)
}


def generate_one(module_name, element, outdir):
    gen = GENERATORS[module_name]
    rows, cases = gen.build_cases(element)
    return common.write_element(outdir, element, gen.FAMILY, gen.GENERATOR, rows, cases)


def main(argv):
    if len(argv) != 2:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    outdir = argv[1]
    os.makedirs(outdir, exist_ok=True)
    for old in glob.glob(os.path.join(outdir, "*.json")):
        os.remove(old)
    start = time.time()
    jobs = [(name, element) for name, gen in GENERATORS.items() for element in gen.ELEMENTS]
    workers = max(1, min(len(jobs), os.cpu_count() or 1))
    with ProcessPoolExecutor(max_workers=workers) as pool:
        futures = [pool.submit(generate_one, name, element, outdir) for name, element in jobs]
        counts = [f.result() for f in futures]
    # Expression time functions: one file of (text, t, f, f', f''), not a constraint element.
    counts.append(gen_expressions.main(outdir))
    print(f"oracle: wrote {len(counts)} files, {sum(counts)} cases to {outdir} "
          f"in {time.time() - start:.1f} s ({workers} processes)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
