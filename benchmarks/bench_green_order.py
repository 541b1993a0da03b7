"""A geometric fill-reducing ordering for graph_green below the band, against CHOLMOD's AMD: measured, not adopted.

Question (issue 28, item 8): most of the peer's one-column time at l = 12 is CHOLMOD's symbolic
analysis. Does the flake's own geometry give an ordering as good as AMD's for less, so that a
full-matrix real factorisation (CHOLMOD analysing a permuted H with ``ordering_method="natural"``)
beats the rotation-sector route of graph_green and the peer?

The geometric ordering tried here is a nested dissection by polar angle, O(N) in vectorised numpy
apart from one argsort: the disk (or, for a sector block, the cone of one wedge with its two sides
glued) is bisected recursively by rays from the centre. An edge whose ends fall on the two sides of
a ray puts one end into that ray's separator; leaves of about ``--leaf`` sites are eliminated
outer ring first, each separator after both halves it separates (postorder). CHOLMOD takes no user
permutation through scikit-sparse, so H is permuted symmetrically and analysed in natural order.

Printed, per flake (best of ``--repeat``, the variants interleaved; the machine is shared):

1. the ordering's own time, the permutation of H, and for every ordering (AMD, the geometric one,
   METIS with ``--metis``): CHOLMOD's analysis, numeric simplicial LDL^T at omega = -2.95, one solve,
   nnz(L) and the factorisation flops sum_j c_j^2 (c_j the column counts of L);
2. the same for the sector blocks H_0 (real) and H_1 (complex) (``sector_hamiltonian``), which the
   sector route and the many-omega scan factorise and solve with;
3. one column at omega = -2.95 and -3.5: graph_green from the lattice (today's route), a full-matrix
   prototype with the geometric order doing the same proof work (H built from the lattice, the
   memory count of L, the factorisation, the column, three steps of inverse iteration for the
   Collatz-Wielandt bound of E0, the residual), and the peer
   ``cholmod.cholesky(H, beta=-omega).solve_A(e_j)`` on a prebuilt H; ratio = peer time / time;
4. 16 omegas by one analysis and a refactorisation + solve per omega (the direct path graph_green
   takes below about 20 omegas), AMD against the geometric order (its ordering and permutation
   counted).

Usage: ``python benchmarks/bench_green_order.py [--rings 10,12] [--repeat 3] [--leaf 8] [--metis]``.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np
import scipy.sparse as sp

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import interleaved, machine, peak_rss_mb  # noqa: E402


def angular_dissection(theta: np.ndarray, ring: np.ndarray, ei: np.ndarray, ej: np.ndarray,
                       leaf: int = 8) -> np.ndarray:
    """Nested dissection by angle: an elimination order (perm[k] = the k-th site eliminated).

    ``theta`` in [0, 2 pi) per site, ``ring`` its ring, (ei, ej) the edges. The angle is cut into
    2^D cells (about ``leaf`` sites each); the cut between two halves of a tree node is the ray
    at the node's middle angle. Each edge crossing a cut puts its end of larger angle code into
    the separator of the coarsest node whose cut it crosses.
    """
    n = theta.shape[0]
    depth_max = max(1, int(np.ceil(np.log2(max(n / leaf, 2)))))
    code = (theta * ((1 << depth_max) / (2 * np.pi))).astype(np.int64)
    np.clip(code, 0, (1 << depth_max) - 1, out=code)
    ci, cj = code[ei], code[ej]
    diff = ci ^ cj
    cut = np.flatnonzero(diff)
    top_bit = np.frexp(diff[cut].astype(np.float64))[1] - 1      # the highest differing bit
    node_depth = depth_max - 1 - top_bit
    end = np.where(ci[cut] > cj[cut], ei[cut], ej[cut])
    depth = np.full(n, depth_max, dtype=np.int64)
    np.minimum.at(depth, end, node_depth)
    # postorder: a node after the last leaf of its subtree, deeper nodes first; in a leaf the
    # outer rings first
    last_leaf = (((code >> (depth_max - depth)) + 1) << (depth_max - depth)) - 1
    rings = int(ring.max()) + 2
    inner = np.where(depth == depth_max, rings - ring, 0)
    key = (last_leaf * (depth_max + 1) + (depth_max - depth)) * rings + inner
    return np.argsort(key, kind="stable")


def permuted(A: sp.spmatrix, perm: np.ndarray) -> sp.csc_matrix:
    """P A P^T as CSC for the elimination order ``perm`` (row/column k of the result is perm[k])."""
    A = sp.csc_matrix(A)
    n = A.shape[0]
    iperm = np.empty(n, dtype=np.int64)
    iperm[perm] = np.arange(n, dtype=np.int64)
    cols = np.repeat(iperm, np.diff(A.indptr))
    return sp.coo_matrix((A.data, (iperm[A.indices], cols)), shape=A.shape).tocsc()


def edges_of(A: sp.spmatrix) -> tuple[np.ndarray, np.ndarray]:
    """The off-diagonal pattern of a symmetric matrix as edges i < j."""
    A = sp.csc_matrix(A)
    cols = np.repeat(np.arange(A.shape[0], dtype=np.int64), np.diff(A.indptr))
    keep = A.indices < cols
    return A.indices[keep].astype(np.int64), cols[keep]


def fill(factor) -> tuple[int, float]:
    """nnz(L) (diagonal included) and the factorisation flops sum_j c_j^2 of a CHOLMOD LDL^T."""
    c = np.diff(factor.L().indptr).astype(np.float64)
    return int(c.sum()), float(c @ c)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--rings", default="10,12")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--leaf", type=int, default=8)
    ap.add_argument("--metis", action="store_true", help="also CHOLMOD's METIS ordering (8 s at l = 12)")
    args = ap.parse_args(argv)

    from sksparse import cholmod

    from hyperlattice.graph.factor import _factor_counts
    from hyperlattice.graph.green import GraphResolvent, _e0_lower_bound, graph_green
    from hyperlattice.graph.lattice import ring_lattice
    from hyperlattice.graph.operators import hamiltonian
    from hyperlattice.graph.symmetry import rotation_orbits, sector_hamiltonian

    print(machine())
    warnings.simplefilter("ignore")        # CHOLMOD's own warnings are not ours
    for rings in (int(x) for x in args.rings.split(",")):
        lat = ring_lattice(7, 3, rings)
        n, src = lat.sites, 10
        H = hamiltonian(lat).tocsc()
        e = np.zeros(n)
        e[src] = 1.0
        theta = np.mod(np.angle(lat.z), 2 * np.pi)
        ring = lat.ring.astype(np.int64)
        ei, ej = lat.edges[:, 0].astype(np.int64), lat.edges[:, 1].astype(np.int64)
        print(f"\n{{7,3}} l={rings}: {n:,} sites")

        def order():
            return angular_dissection(theta, ring, ei, ej, args.leaf)

        best, out = interleaved({"order": order}, args.repeat)
        perm = out["order"]
        t_order = best["order"]
        best, out = interleaved({"permute": lambda: permuted(H, perm)}, args.repeat)
        Hg, t_perm = out["permute"], best["permute"]
        print(f"geometric order {t_order:.3f} s, permutation of H {t_perm:.3f} s")

        def orderings(A, Ag, label, rhs, omega=-2.95):
            methods = {"AMD": (A, "amd"), "geometric": (Ag, "natural")}
            if args.metis:
                methods["METIS"] = (A, "metis")
            rows = {}
            for name, (M, how) in methods.items():
                reps = 1 if how == "metis" else args.repeat
                b, o = interleaved({"analyse": lambda: cholmod.analyze(M, mode="simplicial", ordering_method=how)},
                                   reps)
                an = o["analyse"]
                b2, o2 = interleaved({"factor": lambda: an.cholesky(M, beta=-omega)}, args.repeat)
                f = o2["factor"]
                b3, _ = interleaved({"solve": lambda: f.solve_A(rhs)}, args.repeat)
                rows[name] = (b["analyse"], b2["factor"], b3["solve"]) + fill(f)
            a = rows["AMD"]
            for name, (ta, tf, ts, nnz, flops) in rows.items():
                print(f"  {label} {name:9s}: analyse {ta:.4f} s, factorise {tf:.4f} s, solve {ts:.4f} s; "
                      f"nnz(L) {nnz:,} ({nnz / a[3]:.2f}x AMD), flops {flops:.3g} ({flops / a[4]:.2f}x AMD)")
            return rows

        orderings(H, Hg, "H      ", e)
        orbits = rotation_orbits(lat)
        reps = orbits.representatives
        # the cone of one wedge: angle times p, the two sides glued
        th_b = np.mod(np.angle(lat.z[reps]) * lat.p, 2 * np.pi)
        blocks = {}
        for m in (0, 1):
            B = sp.csc_matrix(sector_hamiltonian(lat, m))
            # a Hermitian diagonal is real: a rounding-level imaginary part (the phases of ring 1
            # summed) makes CHOLMOD refuse the block
            B.setdiag(B.diagonal().real)
            blocks[m] = B
        bi, bj = edges_of(blocks[1])
        best, out = interleaved({"order": lambda: angular_dissection(th_b, ring[reps], bi, bj, args.leaf)},
                                args.repeat)
        bperm = out["order"]
        print(f"sector blocks ({orbits.size:,} orbits): geometric order {best['order']:.4f} s")
        rng = np.random.default_rng(0)
        for m, B in blocks.items():
            rhs = rng.standard_normal(orbits.size) * (1.0 if m == 0 else (1.0 + 1.0j))
            orderings(B, permuted(B, bperm), f"H_{m}    ", rhs)

        def prototype(omega):
            # a full-matrix route with the geometric order and the proof work graph_green does
            Hl = hamiltonian(lat).tocsc()
            p = angular_dissection(theta, ring, ei, ej, args.leaf)
            Hp = permuted(Hl, p)
            an = cholmod.analyze(Hp, mode="simplicial", ordering_method="natural")
            # the count of L before numeric work, as graph.factor makes for every analysis
            _factor_counts(Hl, p)
            f = an.cholesky(Hp, beta=-omega)
            if not np.all(f.D() > 0):
                raise RuntimeError("not below the band")

            def solve(b):
                y = f.solve_A(b[p])
                x = np.empty_like(y)
                x[p] = y
                return x

            x = solve(e)
            v = np.ones(n)
            for _ in range(3):
                v = solve(v)
                v /= np.abs(v).max()
            e0 = _e0_lower_bound(Hl, v)
            r = e - (Hl @ x - omega * x)
            return x, float(np.linalg.norm(r) / (e0 - omega) / np.linalg.norm(x))

        for omega in (-2.95, -3.5):
            best, out = interleaved({
                "graph_green": lambda: graph_green(GraphResolvent(lat), omega, src),
                "geometric prototype": lambda: prototype(omega),
                "peer": lambda: cholmod.cholesky(H, beta=-omega).solve_A(e),
            }, args.repeat)
            ref = out["peer"]
            dev = float(np.max(np.abs(out["geometric prototype"][0] - ref)) / np.max(np.abs(ref)))
            print(f"one column, omega={omega}: graph_green {best['graph_green']:.3f} s (ratio "
                  f"{best['peer'] / best['graph_green']:.2f}), geometric prototype {best['geometric prototype']:.3f} s "
                  f"(ratio {best['peer'] / best['geometric prototype']:.2f}), peer {best['peer']:.3f} s; prototype "
                  f"deviation {dev:.1e}, proved relative error <= {out['geometric prototype'][1]:.1e}")

        oms = np.linspace(-3.5, -2.935, 16)

        def direct(geo):
            if geo:
                p = angular_dissection(theta, ring, ei, ej, args.leaf)
                M, b, how = permuted(H, p), e[p], "natural"
            else:
                M, b, how = H, e, "amd"
            an = cholmod.analyze(M, mode="simplicial", ordering_method=how)
            f = None
            for w in oms:
                if f is None:
                    f = an.cholesky(M, beta=-w)
                else:
                    f.cholesky_inplace(M, beta=-w)
                f.solve_A(b)

        best, _ = interleaved({"AMD": lambda: direct(False), "geometric": lambda: direct(True)}, args.repeat)
        print(f"16 omegas, one analysis + refactorise and solve per omega: AMD {best['AMD']:.3f} s, "
              f"geometric {best['geometric']:.3f} s (ratio {best['AMD'] / best['geometric']:.2f})")
    print(f"peak RSS {peak_rss_mb():.0f} MB")


if __name__ == "__main__":
    main()
