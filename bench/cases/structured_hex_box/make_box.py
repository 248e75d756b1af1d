#!/usr/bin/env python3
"""Writes box.inp: a steel cantilever box of nx x ny x nz C3D8 hexahedra (ids from 1, i fastest),
0.25 x 0.05 x 0.03 m, with node sets FIX (x = 0 face) and TIP (the middle 10 x 10 nodes of the
x = L face: 100 master nodes). Default 90 x 20 x 36 elements: 70,707 nodes, 212,121 DOFs.
Usage: make_box.py [nx ny nz] (run in this folder; case.yaml reads box.inp)."""
import sys

nx, ny, nz = (int(a) for a in sys.argv[1:4]) if len(sys.argv) == 4 else (90, 20, 36)
lx, ly, lz = 0.25, 0.05, 0.03


def node(i, j, k):
    return 1 + i + (nx + 1) * (j + (ny + 1) * k)


with open("box.inp", "w") as f:
    f.write("*NODE\n")
    for k in range(nz + 1):
        for j in range(ny + 1):
            for i in range(nx + 1):
                f.write(f"{node(i, j, k)},{lx * i / nx:.17g},{ly * j / ny:.17g},{lz * k / nz:.17g}\n")
    f.write("*ELEMENT,TYPE=C3D8,ELSET=EALL\n")
    e = 1
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                n = [node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k), node(i, j + 1, k),
                     node(i, j, k + 1), node(i + 1, j, k + 1), node(i + 1, j + 1, k + 1),
                     node(i, j + 1, k + 1)]
                f.write(f"{e}," + ",".join(map(str, n)) + "\n")
                e += 1

    def nset(name, ids):
        f.write(f"*NSET,NSET={name}\n")
        for s in range(0, len(ids), 16):
            f.write(",".join(map(str, ids[s:s + 16])) + "\n")

    nset("FIX", [node(0, j, k) for k in range(nz + 1) for j in range(ny + 1)])
    j0, k0 = (ny - 9) // 2, (nz - 9) // 2
    nset("TIP", [node(nx, j0 + j, k0 + k) for k in range(10) for j in range(10)])
print(f"box.inp: {(nx + 1) * (ny + 1) * (nz + 1)} nodes, {3 * (nx + 1) * (ny + 1) * (nz + 1)} DOFs")
