"""FreeFem++ for the perf scripts: the mesh of a channel cell with a disc,
and running a script for the numbers of its last line that starts with
RESULT."""
import math
import subprocess
import sys


def run_result(path, script, nonzero_field):
    """Writes SCRIPT to PATH, runs it and returns the fields of its last
    RESULT line (strings, the word RESULT first). FreeFem++ reports some
    failed solves (memory) only by a zero solution: field `nonzero_field`
    must not be zero."""
    with open(path, "w") as f:
        f.write(script)
    done = subprocess.run(["FreeFem++-nw", "-v", "0", path], capture_output=True, text=True)
    result = [line.split() for line in done.stdout.splitlines() if line.startswith("RESULT")]
    if done.returncode != 0 or not result:
        sys.exit(f"FreeFem++ failed on {path}:\n{done.stdout[-2000:]}\n{done.stderr[-2000:]}")
    if not float(result[-1][nonzero_field]) != 0:
        sys.exit(f"FreeFem++ gave a zero solution on {path}: the solve failed (too fine a mesh?)")
    return result[-1]


def channel_with_disc(length, height, radius, segments):
    """FreeFem++ lines: the cell [0, length] x [0, height], periodic along x
    (labels 2 and 4), walls at y = 0 (label 1) and y = height (3), a disc of
    `radius` at the centre (5, twice as finely divided), `segments`
    boundary segments along the height; the mesh Th and the Taylor-Hood
    space Wh with [u, v, p] and the test functions [uu, vv, pp]. Defines L,
    H, R, cx, cy."""
    h = height / segments
    along = math.ceil(length / h)
    return f"""real L = {length!r}, H = {height!r}, R = {radius!r}, cx = L/2, cy = H/2;
border bottom(t=0, 1) {{x = L*t; y = 0; label = 1;}}
border right(t=0, 1) {{x = L; y = H*t; label = 2;}}
border top(t=1, 0) {{x = L*t; y = H; label = 3;}}
border left(t=1, 0) {{x = 0; y = H*t; label = 4;}}
border disc(t=0, 2*pi) {{x = cx + R*cos(t); y = cy + R*sin(t); label = 5;}}
mesh Th = buildmesh(bottom({along}) + right({segments}) + top({along}) + left({segments})
                    + disc(-{math.ceil(2 * math.pi * radius / h * 2)}));
fespace Wh(Th, [P2, P2, P1], periodic=[[2, y], [4, y]]);
Wh [u, v, p], [uu, vv, pp];
"""
