#!/usr/bin/env python3
"""Write sector.inp: one of N sectors of a simple bladed disk with an under-platform damper.

The mesh of examples/05_bladed_disk_damper (README.md). Run it again after changing a parameter
below; the committed sector.inp is its output with these values:

    python3 examples/05_bladed_disk_damper/make_sector.py examples/05_bladed_disk_damper/sector.inp

Geometry, in cylindrical coordinates (r, theta, z) about the z axis, theta in degrees, sector 0
spanning theta 0..360/N (every region is a structured grid of C3D8I hexahedra whose corner nodes
lie at the (r, theta, z) grid points, so the element faces are flat and the low boundary theta = 0
rotated by 360/N lands exactly on the high boundary theta = 360/N):

    disk      r 0.10..0.18, the whole sector (its low/high faces are the cyclic boundaries),
              clamped at the bore r = 0.10 (node set HUB);
    neck      r 0.18..0.21 under the blade;
    platform  r 0.21..0.216, theta 0.5..14.5: it stops 0.5 degrees short of each boundary, so
              neighbouring platforms do not touch (a 1-degree slot between them);
    blade     r 0.216..0.30, a straight plate 2 degrees thick (theta 6.5..8.5), chord 0.03 along z;
    damper    r 0.204..0.21, theta 13.5..16.5: a separate part (its own nodes, element set DAMPER)
              under the slot between this blade's platform (theta 13.5..14.5) and the next blade's
              (theta 15.5..16.5 = the next sector's 0.5..1.5). Its top is crowned: the nodes at
              theta 14.5 and 15.5 lie CHAMFER below r = 0.21, so it touches each platform's
              underside along one line of nodes (theta 13.5 and 16.5, node to node); spinning, the
              centrifugal force presses it onto them. (With a flat top the platforms, bent by their
              own centrifugal load, rest on the damper's outer edges only and the inner nodes hang
              a fraction of a micrometre open: every vibration opens and closes them.)

Sets written (ids of sector 0):
    BLADE_DISK, DAMPER     element sets of the two bodies
    HUB                    the bore, clamped
    LOW, HIGH              the disk's cyclic boundaries (theta 0 and 360/N)
    PLATFORM_OWN           platform underside nodes the damper touches (theta 13.5)
    PLATFORM_NEXT_COPY     platform underside nodes at theta 1.5: their copies in the next
                           sector touch the damper's DAMPER_NEXT nodes
    DAMPER_OWN             damper top nodes on this blade's platform (theta 13.5)
    DAMPER_NEXT            damper top nodes on the next blade's platform (theta 16.5)
    TIP                    one node at the blade tip's trailing corner (the forced node)
and damper_next_pairs.csv beside the mesh: one line "damper node,blade node" per pair of the
contact with the next sector (the blade node is the sector-0 copy, PLATFORM_NEXT_COPY).
"""

import math
import os
import sys

N = 24  # sectors (blades)
Z = [0.0, 0.01, 0.02, 0.03]  # axial levels, m (every part)
DISK_R = [0.10, 0.12, 0.14, 0.16, 0.18]
DISK_T = [0.0, 3.0, 6.5, 8.5, 12.0, 15.0]
NECK_R = [0.18, 0.195, 0.21]
BLADE_T = [6.5, 8.5]
PLATFORM_R = [0.21, 0.216]
PLATFORM_T = [0.5, 1.5, 3.0, 6.5, 8.5, 12.0, 13.5, 14.5]
BLADE_R = [0.216, 0.23, 0.244, 0.258, 0.272, 0.286, 0.30]
DAMPER_R = [0.204, 0.21]
DAMPER_T = [13.5, 14.5, 15.5, 16.5]
CHAMFER = 1.0e-4  # m: the damper's top is lowered by this at theta 14.5 and 15.5 (a crowned top)


def main(path):
    assert abs(DISK_T[-1] - 360.0 / N) < 1e-12
    nodes = {}  # (part, r, theta, z) -> id; part 0 blade-disk (merged), 1 damper
    coords = []

    def node(part, r, t, z):
        key = (part, round(r, 9), round(t, 9), round(z, 9))
        if key not in nodes:
            nodes[key] = len(coords) + 1
            a = math.radians(t)
            if part == 1 and r == DAMPER_R[-1] and t in (DAMPER_T[1], DAMPER_T[2]):
                r -= CHAMFER
            coords.append((r * math.cos(a), r * math.sin(a), z))
        return nodes[key]

    elements = {"BLADE_DISK": [], "DAMPER": []}

    def block(part, rs, ts, elset):
        for i in range(len(rs) - 1):
            for j in range(len(ts) - 1):
                for k in range(len(Z) - 1):
                    r0, r1, t0, t1, z0, z1 = rs[i], rs[i + 1], ts[j], ts[j + 1], Z[k], Z[k + 1]
                    # C3D8 order: the face z0 counter-clockwise seen from +z, then z1.
                    elements[elset].append([
                        node(part, r0, t0, z0), node(part, r1, t0, z0),
                        node(part, r1, t1, z0), node(part, r0, t1, z0),
                        node(part, r0, t0, z1), node(part, r1, t0, z1),
                        node(part, r1, t1, z1), node(part, r0, t1, z1)])

    block(0, DISK_R, DISK_T, "BLADE_DISK")
    block(0, NECK_R, BLADE_T, "BLADE_DISK")
    block(0, PLATFORM_R, PLATFORM_T, "BLADE_DISK")
    block(0, BLADE_R, BLADE_T, "BLADE_DISK")
    block(1, DAMPER_R, DAMPER_T, "DAMPER")

    def select(part, r=None, ts=None):
        out = []
        for (p, rr, tt, zz), i in nodes.items():
            if p == part and (r is None or abs(rr - r) < 1e-9) and (ts is None or
                                                                     any(abs(tt - t) < 1e-9
                                                                         for t in ts)):
                out.append((tt, zz, i))
        return [i for _, _, i in sorted(out)]

    sets = {
        "HUB": select(0, r=DISK_R[0]),
        "LOW": select(0, ts=[0.0]),
        "HIGH": select(0, ts=[DISK_T[-1]]),
        "PLATFORM_OWN": select(0, r=PLATFORM_R[0], ts=[13.5]),
        "PLATFORM_NEXT_COPY": select(0, r=PLATFORM_R[0], ts=[1.5]),
        "DAMPER_OWN": select(1, r=DAMPER_R[-1], ts=[13.5]),
        "DAMPER_NEXT": select(1, r=DAMPER_R[-1], ts=[16.5]),
        "TIP": [nodes[(0, BLADE_R[-1], BLADE_T[-1], Z[-1])]],
    }
    # The damper's next-side nodes sorted by (theta, z) are the copies' order shifted by 360/N.
    pairs = list(zip(sets["DAMPER_NEXT"], sets["PLATFORM_NEXT_COPY"]))
    for a, b in pairs:
        xa = coords[a - 1]
        xb = coords[b - 1]
        c, s = math.cos(2 * math.pi / N), math.sin(2 * math.pi / N)
        xr = (c * xb[0] - s * xb[1], s * xb[0] + c * xb[1], xb[2])
        assert max(abs(xr[i] - xa[i]) for i in range(3)) < 1e-12

    with open(path, "w") as f:
        f.write("** %d-blade disk sector with an under-platform damper: make_sector.py\n" % N)
        f.write("*NODE\n")
        for i, (x, y, z) in enumerate(coords):
            f.write("%d, %.15g, %.15g, %.15g\n" % (i + 1, x, y, z))
        eid = 1
        for name, conn in elements.items():
            f.write("*ELEMENT, TYPE=C3D8I, ELSET=%s\n" % name)
            for e in conn:
                f.write("%d, %s\n" % (eid, ", ".join(str(n) for n in e)))
                eid += 1
        for name, ids in sets.items():
            f.write("*NSET, NSET=%s\n" % name)
            for n in range(0, len(ids), 8):
                f.write(", ".join(str(i) for i in ids[n:n + 8]) + "\n")
    with open(os.path.join(os.path.dirname(path) or ".", "damper_next_pairs.csv"), "w") as f:
        f.write("# damper node (DAMPER_NEXT), blade node (PLATFORM_NEXT_COPY; its copy in the "
                "next sector touches it)\n")
        for a, b in pairs:
            f.write("%d,%d\n" % (a, b))
    print("%s: %d nodes, %d elements (%d blade-disk, %d damper)" %
          (path, len(coords), sum(len(e) for e in elements.values()), len(elements["BLADE_DISK"]),
           len(elements["DAMPER"])))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "sector.inp")
