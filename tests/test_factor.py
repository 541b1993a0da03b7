"""The sparse-direct layer (graph/factor.py): inertia, solves, refactorisation, backends, memory refusal."""

import builtins
import sys

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp

from hyperlattice.errors import HyperlatticeError
from hyperlattice.graph import factor as F
from hyperlattice.graph.lattice import ring_lattice
from hyperlattice.graph.operators import hamiltonian

BACKENDS = ["superlu", pytest.param("cholmod", marks=pytest.mark.skipif(
    not F.cholmod_available(), reason="scikit-sparse (CHOLMOD) not installed"))]


@pytest.fixture(scope="module")
def flake():
    return ring_lattice(7, 3, 4)


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("flux", [0.0, 0.13])
def test_inertia_matches_dense_eigvalsh(flake, backend, flux):
    # reference: LAPACK eigvalsh of the dense H; shifts kept > 1e-6 away from every level so that the
    # count cannot depend on rounding (the factor's backward error is ~1e-14 here)
    H = hamiltonian(flake, flux=flux)
    w = sla.eigvalsh(H.toarray())
    an = F.analyze(H, backend=backend)
    assert an.backend == backend
    for sigma in (-3.5, -2.5, -0.77, 0.3, 1.7, 3.5):
        assert np.min(np.abs(w - sigma)) > 1e-6
        f = an.factor(sigma)
        assert f.backend == backend and f.proved
        assert f.negatives == int(np.count_nonzero(w < sigma)), sigma


@pytest.mark.parametrize("backend", BACKENDS)
def test_solves_one_and_many_rhs(flake, backend):
    H = hamiltonian(flake, flux=0.21)
    n = H.shape[0]
    f = F.factorize(H, 0.4, backend=backend)
    b = np.random.default_rng(1).standard_normal((n, 4)) + 0j
    x = f.solve(b)
    dense = H.toarray() - 0.4 * np.eye(n)
    # the residual is bounded by the backward error ~ n eps ||H|| ||x||
    assert np.max(np.abs(dense @ x - b)) < 1e-10 * max(1.0, np.abs(x).max())
    x1 = f.solve(b[:, 0])
    assert x1.shape == (n,)
    np.testing.assert_allclose(x1, x[:, 0], rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("backend", BACKENDS)
def test_refactorisation_equals_fresh_factorisation(flake, backend):
    H = hamiltonian(flake)
    n = H.shape[0]
    b = np.random.default_rng(2).standard_normal(n)
    first = F.factorize(H, -3.3, backend=backend)
    again = first.refactor(-2.95)
    fresh = F.factorize(H, -2.95, backend=backend)
    assert again.analysis is first.analysis
    # same matrix, same order: equal to rounding (both solutions ~ 1/dist ~ 10, eps-level differences)
    np.testing.assert_allclose(again.solve(b), fresh.solve(b), rtol=1e-11, atol=1e-13)
    assert again.negatives == fresh.negatives == 0


@pytest.mark.parametrize("backend", BACKENDS)
def test_positive_definite_proved_below_the_band(flake, backend):
    H = hamiltonian(flake)
    e0 = sla.eigvalsh(H.toarray())[0]
    below = F.factorize(H, e0 - 1e-3, backend=backend, positive=True)
    assert below.positive_definite and below.negatives == 0
    above = F.factorize(H, e0 + 1e-3, backend=backend, positive=True)
    assert not above.positive_definite and above.negatives == 1


def test_complex_shift_gives_lu_without_inertia(flake):
    H = hamiltonian(flake)
    f = F.factorize(H, 0.3 + 0.01j)
    assert f.kind == "LU" and f.negatives is None and not f.proved
    b = np.zeros(H.shape[0])
    b[3] = 1.0
    x = f.solve(b)
    np.testing.assert_allclose((H - (0.3 + 0.01j) * sp.identity(H.shape[0])) @ x, b, atol=1e-10)


def test_zero_pivot_is_one_sentence():
    # a 2x2 matrix with eigenvalue exactly 1: the shift sigma = 1 leaves an exactly singular factor
    H = sp.csc_matrix(np.array([[1.0, 0.0], [0.0, 2.0]]))
    with pytest.raises(HyperlatticeError, match="eigenvalue"):
        F.factorize(H, 1.0, backend="superlu")


def test_memory_refusal_before_work(flake):
    H = hamiltonian(flake)
    with pytest.raises(F.FactorMemoryError, match=r"needs about .* more than the .* allowed by max_bytes") as info:
        F.analyze(H, max_bytes=1000)
    assert isinstance(info.value, MemoryError) and isinstance(info.value, HyperlatticeError)
    assert "\n" not in str(info.value)


def test_available_memory_respects_the_address_space_limit():
    import resource
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    assert F.available_memory() > 0
    if soft != resource.RLIM_INFINITY:  # pragma: no cover - the suite normally runs without a limit
        assert F.available_memory() <= soft


def test_fallback_to_superlu_is_taken_and_named(flake, monkeypatch):
    # CHOLMOD made unimportable: "auto" silently takes SuperLU, an explicit "cholmod" warns and names it
    real_import = builtins.__import__

    def no_sksparse(name, *args, **kwargs):
        if name.startswith("sksparse"):
            raise ImportError("No module named 'sksparse'")
        return real_import(name, *args, **kwargs)

    monkeypatch.delitem(sys.modules, "sksparse", raising=False)
    monkeypatch.delitem(sys.modules, "sksparse.cholmod", raising=False)
    monkeypatch.setattr(builtins, "__import__", no_sksparse)
    assert not F.cholmod_available()
    H = hamiltonian(flake)
    assert F.factorize(H, -3.5).backend == "superlu"
    with pytest.warns(F.SolverFallbackWarning, match="SuperLU ran instead"):
        f = F.factorize(H, -3.5, backend="cholmod")
    assert f.backend == "superlu" and f.positive_definite


def test_bad_backend_is_a_value_error(flake):
    with pytest.raises(ValueError, match="backend"):
        F.analyze(hamiltonian(flake), backend="mumps")


def test_environment_variable_hides_cholmod(flake, monkeypatch):
    # HYPERLATTICE_FACTOR_BACKEND=superlu: the SuperLU-only configuration (pytest --superlu-only, CI)
    monkeypatch.setenv(F.BACKEND_ENV, "superlu")
    assert not F.cholmod_available() and F.resolve_backend("auto") == "superlu"
    assert F.factorize(hamiltonian(flake), -3.5).backend == "superlu"
    monkeypatch.setenv(F.BACKEND_ENV, "")
    assert F.resolve_backend("auto") == ("cholmod" if F._cholmod() is not None else "superlu")


@pytest.mark.parametrize("backend", ["superlu", "cholmod"])
@pytest.mark.parametrize("positive", [False, True])
def test_a_shift_at_an_eigenvalue_is_a_tie_not_a_proof(backend, positive):
    # issue 28 item 6: sigma = E0 (to rounding) reported negatives = 0 as "proved"
    import hyperlattice as hl
    from hyperlattice.graph.factor import FactorizationError, cholmod_available as have_cholmod, factorize

    if backend == "cholmod" and not have_cholmod():
        pytest.skip("CHOLMOD is not installed")
    H = hl.hamiltonian(hl.ring_lattice(7, 3, 2)).tocsc()
    e = np.linalg.eigvalsh(H.toarray())
    at = factorize(H, float(e[0]), backend=backend, positive=positive)
    assert at.tie and not at.proved
    below = factorize(H, float(e[0]) - 1e-3, backend=backend, positive=positive)
    assert below.proved and not below.tie and below.negatives == 0
    between = factorize(H, 0.5 * float(e[0] + e[1]), backend=backend)
    assert between.proved and between.negatives == 1
    # an exact zero pivot: one sentence, no backend text
    with pytest.raises(FactorizationError, match=r"singular to working precision \(the shift is an eigenvalue\)\.$"):
        factorize(sp.diags([1.0, 2.0, 3.0, 4.0]).tocsc(), 2.0, backend=backend, positive=positive)


@pytest.mark.parametrize("backend", ["superlu", "cholmod"])
def test_a_non_symmetric_matrix_is_refused_for_an_inertia_count(backend):
    from hyperlattice.graph.factor import cholmod_available as have_cholmod, factorize

    if backend == "cholmod" and not have_cholmod():
        pytest.skip("CHOLMOD is not installed")
    N = sp.csc_matrix(np.array([[1.0, 2.0], [0.0, 1.0]]))
    with pytest.raises(ValueError, match=r"must be symmetric for an LDL\^T .* pivoting=True"):
        factorize(N, 0.0, backend=backend)
    lu = factorize(N, 0.0, pivoting=True)                # a plain LU takes any matrix
    assert lu.negatives is None and not lu.proved and np.allclose(N @ lu.solve(np.ones(2)), 1.0)


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_matrix_built_symmetric_skips_the_check_and_the_norm_follows_the_values(flake, backend):
    # new values on the analysed pattern: checked by default, taken as built with symmetric=True (the
    # sector blocks); the 1-norm used for ties is that of the matrix factorised, whichever path ran
    H = hamiltonian(flake).tocsc()
    an = F.analyze(H, backend=backend)
    assert an.norm == pytest.approx(3.0)
    twice = an.matrix.copy()
    twice.data *= 2.0
    f = an.factor(-7.0, positive=True, matrix=twice, symmetric=True)
    assert f.negatives == 0 and an.norm == pytest.approx(6.0) and f.proved
    skew = an.matrix.copy()
    upper = np.repeat(np.arange(skew.shape[0]), np.diff(skew.indptr)) > skew.indices
    skew.data[upper] *= 1.5
    with pytest.raises(ValueError, match="must be symmetric"):
        an.factor(-7.0, matrix=skew)


@pytest.mark.parametrize("value", ["junk", "superLU_dist", "0"])
def test_a_misspelt_backend_variable_is_refused(value, monkeypatch, capsys):
    # issue 28 item 6: HYPERLATTICE_FACTOR_BACKEND=junk was silently taken as auto
    from hyperlattice.cli import main

    monkeypatch.setenv("HYPERLATTICE_FACTOR_BACKEND", value)
    with pytest.raises(ValueError, match=r"HYPERLATTICE_FACTOR_BACKEND = .* is not one of auto, cholmod, superlu"):
        F.resolve_backend("auto")
    assert main(["lattice", "--rings", "1"]) == 2           # the CLI refuses before any command runs
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "HYPERLATTICE_FACTOR_BACKEND" in err


@pytest.mark.parametrize("value, backend", [("SuperLU", "superlu"), (" auto ", None), ("", None)])
def test_the_backend_variable_values(value, backend, monkeypatch):
    monkeypatch.setenv("HYPERLATTICE_FACTOR_BACKEND", value)
    want = backend or ("cholmod" if F.cholmod_available() else "superlu")
    assert F.resolve_backend("auto") == want


def test_with_values_takes_new_values_on_the_analysed_pattern_and_checks_them():
    H = hamiltonian(ring_lattice(7, 3, 3)).tocsc()
    an = F.analyze(H, backend="superlu")
    view = an.with_values(2.0 * an.matrix.data)             # 2H on the analysed pattern
    below = int(np.sum(np.linalg.eigvalsh(2 * H.toarray()) < -4.0))
    assert below > 0 and view.factor(-4.0).negatives == below
    assert an.factor(-4.0).negatives == 0                     # the analysis itself still holds H
    with pytest.raises(ValueError, match="do not fit"):
        an.with_values(an.matrix.data[:-1])
    with pytest.raises(ValueError, match="complex"):
        an.with_values(an.matrix.data * (1 + 1e-3j))
    with pytest.raises(ValueError, match="NaN"):
        an.with_values(np.full(an.matrix.nnz, np.nan))
    cplx = F.analyze(H.astype(complex), backend="superlu")
    data = cplx.matrix.data.copy()
    data[F._diag_positions(cplx.matrix)] += 1e-20j            # a Hermitian diagonal is made real
    assert np.all(cplx.with_values(data).matrix.diagonal().imag == 0)
