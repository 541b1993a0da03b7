"""Another machine's rounding, simulated on this one (``pytest --rounding-noise SEED``).

A symmetric eigensolver returns each eigenvalue with an error of a few units of
:math:`\\varepsilon\\,\\|H\\|`; which few depends on the BLAS kernel (AVX2, AVX-512, FMA), the
number of threads and the CPU. Its eigenvectors come with an arbitrary sign (real) or phase
(complex). A test or a result that depends on those last bits passes on the machine it was written
on and fails on the next one. This module makes the next machine: it wraps the eigensolvers the
package calls (numpy's and SciPy's dense ``eigh``/``eigvalsh``, ``eigh_tridiagonal``, ARPACK's
``eigsh``) so that every eigenvalue moves by up to ``ulps`` units of :math:`\\varepsilon
\\max|w|` and every eigenvector column gets a random sign or phase; the eigenvalues stay
ascending, as LAPACK returns them.

The perturbation is a deterministic function of the input's bytes and the seed: the same
computation twice gives the same answer (as on one machine), another seed is another machine.
The moves stay far inside the package's own error bound (:func:`hyperlattice._ties.
eigenvalue_tolerance`, 16 n eps ||H||), so everything the package decides with that bound, and
every test that compares within a tolerance derived from the computation's error, passes with any
seed; a test that reads the sign of a zero mode, the order of a degenerate pair or a printed
last digit fails for some seeds.

Only this process is perturbed: CLI subprocesses a test starts compute with the real solvers.
"""

from __future__ import annotations

import hashlib

import numpy as np

#: the solvers wrapped: (module, attribute)
TARGETS = (("numpy.linalg", "eigh"), ("numpy.linalg", "eigvalsh"), ("scipy.linalg", "eigh"),
           ("scipy.linalg", "eigvalsh"), ("scipy.linalg", "eigh_tridiagonal"), ("scipy.sparse.linalg", "eigsh"))


def _digest(seed: int, *objs) -> int:
    import scipy.sparse as sp

    h = hashlib.blake2b(str(seed).encode(), digest_size=8)
    for o in objs:
        if isinstance(o, np.ndarray):
            h.update(str((o.shape, o.dtype.str)).encode())
            h.update(np.ascontiguousarray(o).tobytes())
        elif sp.issparse(o):
            o = o.tocsr()
            h.update(str(o.shape).encode())
            for a in (o.data, o.indices, o.indptr):
                h.update(np.ascontiguousarray(a).tobytes())
        elif hasattr(o, "shape") and not np.isscalar(o):
            h.update(str((type(o).__name__, o.shape)).encode())      # a LinearOperator: its shape only
        else:
            h.update(repr(o).encode())
    return int.from_bytes(h.digest(), "little")


def perturb(w, v, key: int, ulps: float):
    """Eigenvalues ``w`` moved by up to ``ulps`` eps max|w|, columns of ``v`` given a random sign/phase."""
    w = np.asarray(w)
    if w.size == 0 or w.dtype.kind != "f":
        return w, v
    rng = np.random.default_rng(key)
    w2 = w + ulps * np.finfo(float).eps * float(np.max(np.abs(w))) * rng.uniform(-1.0, 1.0, w.shape)
    if v is not None:
        v = np.array(v, copy=True)
        if v.ndim == 2 and v.shape[1] == w.shape[-1]:
            if np.iscomplexobj(v):
                v = v * np.exp(2j * np.pi * rng.uniform(size=v.shape[1]))
            else:
                v = v * rng.choice([-1.0, 1.0], size=v.shape[1])
    if w.ndim == 1 and np.all(np.diff(w) >= 0):             # ascending in, ascending out
        order = np.argsort(w2, kind="stable")
        w2 = w2[order]
        if v is not None and v.ndim == 2 and v.shape[1] == w.shape[0]:
            v = v[:, order]
    return w2, v


def _wrap(fn, seed: int, ulps: float):
    def wrapped(a, *args, **kwargs):
        out = fn(a, *args, **kwargs)
        plain = tuple(sorted((k, x) for k, x in kwargs.items() if isinstance(x, (int, float, str, tuple, type(None)))))
        arrays = [x for x in args if isinstance(x, np.ndarray)] + [kwargs.get("v0")]
        key = _digest(seed, fn.__name__, a, *arrays, repr(plain))
        if isinstance(out, tuple):
            w2, v2 = perturb(out[0], out[1], key, ulps)
            return type(out)(w2, v2) if hasattr(out, "_fields") else (w2, v2) + tuple(out[2:])
        return perturb(out, None, key, ulps)[0]

    wrapped.__name__, wrapped.__doc__, wrapped.__wrapped__ = fn.__name__, fn.__doc__, fn
    return wrapped


def install(seed: int, ulps: float = 8.0):
    """Wrap the eigensolvers for this process; returns a function that restores them."""
    import importlib

    saved = []
    for mod_name, attr in TARGETS:
        mod = importlib.import_module(mod_name)
        fn = getattr(mod, attr)
        saved.append((mod, attr, fn))
        setattr(mod, attr, _wrap(fn, seed, ulps))

    def undo():
        for mod, attr, fn in saved:
            setattr(mod, attr, fn)
    return undo
