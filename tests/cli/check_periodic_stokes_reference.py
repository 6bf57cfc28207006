#!/usr/bin/python3
"""The boundary-integral reference for cubic arrays of spheres
(perf/periodic_stokes_spheres.py) against what is known of it:

- its periodic Stokeslet does not depend on the Ewald split (SC, BCC, FCC);
- on the simple cubic array it gives Zick & Homsy's drag K (Table 2, four
  digits) within 0.05 %;
- on the BCC and FCC arrays it gives the K that perf/sphere_arrays.py
  compares PoreSPH with (computed at a higher degree), within 1e-5, so that
  the table there can be made again from the script;
- it refuses a solid fraction at which the spheres would overlap.

Exits 77 (skipped) without SciPy, which the script needs and
`scripts/setup.sh test|tools` installs.

    check_periodic_stokes_reference.py SOURCE_DIR
"""
import os
import sys

source = sys.argv[1]
sys.path.insert(0, os.path.join(source, "perf"))
try:
    import scipy  # noqa: F401
except ImportError:
    print("check_periodic_stokes_reference.py: SciPy is not installed: skipped (scripts/setup.sh tools installs it)")
    sys.exit(77)
import periodic_stokes_spheres as reference  # noqa: E402
from sphere_arrays import DRAG  # noqa: E402

DEGREE = 12
failures = 0
for lattice in ("sc", "bcc", "fcc"):
    split, regular = reference.check_ewald(lattice)
    ok = split < 1e-10 and regular < 1e-10
    failures += not ok
    print(f"{lattice}: Ewald sum changes by {split:.1e} with its split, regular part by {regular:.1e} "
          f"{'ok' if ok else 'FAILED'}")

cases = [("sc", 0.027, 5e-4), ("sc", 0.125, 5e-4), ("sc", 0.216, 5e-4),
         ("bcc", 0.125, 1e-5), ("fcc", 0.216, 1e-5)]
for lattice, phi, tolerance in cases:
    expected = DRAG[lattice][phi]
    K = reference.drag(lattice, phi, DEGREE)[0]
    error = K / expected - 1
    ok = abs(error) < tolerance
    failures += not ok
    print(f"{lattice} phi = {phi}: K = {K:.6f} at degree {DEGREE}, table {expected}, "
          f"{error * 100:+.4f} % {'ok' if ok else 'FAILED'}")
# Overlapping spheres have no answer: refused, not computed.
for lattice, phi in (("sc", 0.6), ("bcc", 0.7), ("fcc", 0.0)):
    try:
        reference.drag(lattice, phi, 4)
        failures += 1
        print(f"{lattice} phi = {phi}: computed, FAILED to refuse")
    except ValueError as error:
        print(f"{lattice} phi = {phi}: refused ({error}) ok")
print("periodic stokes reference ok" if failures == 0 else f"{failures} failed")
sys.exit(1 if failures else 0)
