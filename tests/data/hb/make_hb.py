#!/usr/bin/python3
"""Independent Harwell-Boeing / Matrix Market files for stickslip's io tests (see README.md).

Run with Debian's python3-scipy (scripts/setup.sh installs it). Two commands:

  make_hb.py write OUTDIR
      Writes, with scipy's own writers (code stickslip did not write):
        scipy_rua.hb         scipy.io.hb_write of a seeded random 37 x 23 real unsymmetric matrix
        scipy_rua.triplets   the same matrix as "row col value" lines (1-based, repr of the double)
        scipy_sym.mtx        scipy.io.mmwrite of a seeded random 19 x 19 symmetric matrix
                             (scipy detects the symmetry and writes the lower triangle)
        scipy_sym.triplets   all its stored entries (both triangles) as "row col value" lines
        scipy_dense.mtx      scipy.io.mmwrite of a seeded 7 x 4 dense array ("array" format)
        scipy_dense.triplets its entries as "row col value" lines

  make_hb.py check FILE.hb FILE.triplets
      Reads FILE.hb with scipy.io.hb_read and compares it, bit for bit, with the entries listed in
      FILE.triplets (written by the C++ test). Exit status 0 when equal, 1 otherwise (with a
      message on stderr). scipy reads real unsymmetric assembled (RUA) files only.

Values span many decades (1e-99 .. 1e+99) and both signs, with full 17-digit mantissas.
Exponents stay below 100 because scipy 1.10 writes each real one column narrower than the
format it declares ((3E25.16) in the header, "%24.16E" on the lines; its own reader splits on
blanks): with three-digit exponents a negative value then touches the previous one
("...E+109-9.03...E-198") and no reader, Fortran's or ours, can separate them.
"""
import sys

import numpy as np
import scipy.io
import scipy.sparse as sp
from scipy.io._harwell_boeing.hb import HBInfo  # only to set the title and key


def random_values(rng, n):
    mantissa = rng.uniform(-1.0, 1.0, n)
    exponent = rng.integers(-99, 100, n)
    return mantissa * np.power(10.0, exponent.astype(float))


def write_triplets(path, m):
    c = sp.coo_matrix(m)
    order = np.lexsort((c.row, c.col))
    with open(path, "w") as f:
        for k in order:
            f.write("%d %d %r\n" % (c.row[k] + 1, c.col[k] + 1, float(c.data[k])))


def write(outdir):
    rng = np.random.default_rng(20240611)
    a = sp.random(37, 23, density=0.15, format="csc", random_state=rng)
    a.data = random_values(rng, a.nnz)
    info = HBInfo.from_data(a, title="scipy hb_write test matrix", key="SCIPY")
    scipy.io.hb_write(outdir + "/scipy_rua.hb", a, hb_info=info)
    write_triplets(outdir + "/scipy_rua.triplets", a)

    b = sp.random(19, 19, density=0.2, format="csc", random_state=rng)
    b.data = random_values(rng, b.nnz)
    s = (b + b.T).tocsc()
    s = s + sp.diags(rng.uniform(1.0, 2.0, 19))
    s = sp.csc_matrix(s)
    scipy.io.mmwrite(outdir + "/scipy_sym.mtx", s, symmetry="symmetric", precision=17)
    write_triplets(outdir + "/scipy_sym.triplets", s)

    d = random_values(rng, 28).reshape(7, 4)
    scipy.io.mmwrite(outdir + "/scipy_dense.mtx", d, precision=17)
    write_triplets(outdir + "/scipy_dense.triplets", sp.coo_matrix(d))


def check(hb_path, triplets_path):
    m = sp.csc_matrix(scipy.io.hb_read(hb_path))
    rows, cols, vals = [], [], []
    with open(triplets_path) as f:
        for line in f:
            i, j, v = line.split()
            rows.append(int(i) - 1)
            cols.append(int(j) - 1)
            vals.append(float(v))
    ref = sp.csc_matrix((vals, (rows, cols)), shape=m.shape)
    diff = m - ref
    if diff.nnz and np.max(np.abs(diff.data)) != 0.0:
        sys.stderr.write("scipy hb_read differs from the reference entries: max |diff| = %r\n"
                         % np.max(np.abs(diff.data)))
        return 1
    if m.nnz != len(vals):
        sys.stderr.write("scipy hb_read found %d entries, reference has %d\n" % (m.nnz, len(vals)))
        return 1
    return 0


def main(argv):
    if len(argv) == 3 and argv[1] == "write":
        write(argv[2])
        return 0
    if len(argv) == 4 and argv[1] == "check":
        return check(argv[2], argv[3])
    sys.stderr.write(__doc__)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
