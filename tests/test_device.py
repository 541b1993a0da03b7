"""The device room: resonator lattices with ports (input–output theory), checked against closed forms,
a dense solve, unitarity, reciprocity and the weak-coupling Lorentzian sum."""

from __future__ import annotations

import numpy as np
import pytest

from hyperlattice.device import flat_band_degeneracy, resonator_device, transmission
from hyperlattice.graph.lattice import ring_lattice


def _dense_s(dev, omegas):
    """S by a dense inverse of omega - H + i Gamma/2, frequency by frequency (the reference)."""
    h = dev.hamiltonian().toarray()
    n = h.shape[0]
    gam = np.full(n, dev.kappa_int)
    idx = np.asarray(dev.port_index)
    kap = np.asarray(dev.port_kappa)
    gam[idx] += kap
    out = []
    for w in omegas:
        g = np.linalg.inv(w * np.eye(n) - h + 0.5j * np.diag(gam))
        out.append(np.eye(idx.size) - 1j * np.sqrt(np.outer(kap, kap)) * g[np.ix_(idx, idx)])
    return np.asarray(out)


ONE = np.zeros((1, 1))


@pytest.mark.parametrize("method", ["eigen", "direct", "chebyshev"])
def test_single_resonator_one_port_closed_form(method):
    # S11 = 1 - i kappa / (omega - omega0 + i (kappa + kappa_int)/2)
    w0, k, ki = 5.0, 0.3, 0.1
    dev = resonator_device(ONE, omega0=w0, kappa_int=ki, ports={"0": k})
    w = np.linspace(4.0, 6.0, 41)
    s = transmission(dev, w, method=method).s[:, 0, 0]
    exact = 1 - 1j * k / (w - w0 + 0.5j * (k + ki))
    assert np.max(np.abs(s - exact)) < 1e-12


@pytest.mark.parametrize("method", ["eigen", "direct", "chebyshev"])
def test_single_resonator_two_ports_closed_form(method):
    # input and output line on one resonator: S21 = -i sqrt(k1 k2) / (omega - omega0 + i (k1 + k2 + ki)/2)
    w0, k1, k2, ki = 2.0, 0.2, 0.5, 0.05
    dev = resonator_device(ONE, omega0=w0, kappa_int=ki, ports=[("0", k1), ("0", k2)], shared_ports=True)
    w = np.linspace(1.0, 3.0, 31)
    s = transmission(dev, w, method=method).s
    den = w - w0 + 0.5j * (k1 + k2 + ki)
    assert np.max(np.abs(s[:, 1, 0] - (-1j * np.sqrt(k1 * k2) / den))) < 1e-12
    assert np.max(np.abs(s[:, 0, 0] - (1 - 1j * k1 / den))) < 1e-12
    assert np.max(np.abs(s[:, 1, 1] - (1 - 1j * k2 / den))) < 1e-12


def _device(lossless=False, seed=3, line=True, rings=2):
    lat = ring_lattice(7, 3, rings)
    ports = {"0-1": 0.4, "30-31": 0.6} if line else {"0": 0.4, "20": 0.6, "9": 0.3}
    return resonator_device(lat, line_graph=line, omega0=10.0, J=-1.0, kappa_int=0.0 if lossless else 0.05,
                            ports=ports, sigma_omega=0.05, sigma_J=0.03, seed=seed)


@pytest.mark.parametrize("method", ["eigen", "direct", "chebyshev"])
def test_fast_routes_match_a_dense_solve(method):
    dev = _device(line=method != "direct")
    w = np.linspace(5.0, 15.0, 23)
    tr = transmission(dev, w, method=method)
    ref = _dense_s(dev, w)
    err = np.max(np.abs(tr.s - ref), axis=(1, 2))
    assert np.max(err) < 1e-10
    if method == "chebyshev":
        assert np.all(err <= tr.error_bound)


@pytest.mark.parametrize("method", ["eigen", "direct"])
def test_lossless_s_is_unitary_and_reciprocal(method):
    dev = _device(lossless=True, line=False)
    levels = np.linalg.eigvalsh(dev.hamiltonian().toarray())[:3]
    # on a level exactly: the eigen route borders the pole (exact); the direct route refuses
    w = np.concatenate([np.linspace(5.0, 15.0, 17), levels if method == "eigen" else []])
    s = transmission(dev, w, method=method).s
    eye = np.eye(s.shape[1])
    assert max(np.max(np.abs(m.conj().T @ m - eye)) for m in s) < 1e-10
    ref = _dense_s(dev, w[:17])
    assert np.max(np.abs(s[:17] - ref)) < 1e-10
    assert np.max(np.abs(s - np.transpose(s, (0, 2, 1)))) < 1e-12


def test_loss_makes_s_subunitary():
    s = transmission(_device(), np.linspace(7.0, 13.0, 9)).s
    for m in s:
        assert np.max(np.linalg.eigvalsh(m.conj().T @ m)) <= 1 + 1e-12


def test_weak_coupling_is_the_lorentzian_sum():
    # kappa_p -> 0: S21 -> -i sqrt(k1 k2) sum_n <r2|n><n|r1> / (omega - E_n + i kappa_int/2)
    dev0 = _device(line=False)
    k = 1e-6
    dev = resonator_device(ring_lattice(7, 3, 2), omega0=10.0, J=-1.0, kappa_int=0.05, ports={"0": k, "20": k},
                           sigma_omega=0.05, sigma_J=0.03, seed=3)
    assert np.allclose(dev.omega, dev0.omega)
    e, v = np.linalg.eigh(dev.hamiltonian().toarray())
    w = np.linspace(7.0, 13.0, 301)
    lor = -1j * k * np.sum(v[20][None, :] * v[0][None, :] / (w[:, None] - e[None, :] + 0.025j), axis=1)
    s21 = transmission(dev, w).s[:, 1, 0]
    # relative difference of order kappa_p / kappa_int
    assert np.max(np.abs(s21 - lor)) / np.max(np.abs(lor)) < 1e-3


@pytest.mark.machine_independence
@pytest.mark.parametrize("rings", [2, 3])
def test_flat_band_multiplicity(rings):
    lat = ring_lattice(7, 3, rings)
    dev = resonator_device(lat, line_graph=True, ports={"0-1": 1.0})
    a = -dev.hamiltonian().toarray()              # omega0 = 0, J = 1: H = -A_L
    e = np.linalg.eigvalsh(a)
    assert dev.flat_band == len(lat.edges) - lat.sites
    assert np.sum(np.abs(e + 2) < 1e-9) == dev.flat_band


@pytest.mark.machine_independence
def test_flat_band_of_a_bipartite_graph_counts_one_more():
    ring6 = np.roll(np.eye(6), 1, axis=1)
    ring6 = ring6 + ring6.T
    edges = np.array([[k, (k + 1) % 6] for k in range(6)])
    assert flat_band_degeneracy(edges, 6) == 1       # 6 - 6 + 1
    dev = resonator_device(ring6, line_graph=True, ports={"0-1": 1.0})
    e = np.linalg.eigvalsh(-dev.hamiltonian().toarray())
    assert np.sum(np.abs(e + 2) < 1e-9) == 1


def test_names_and_explicit_disorder():
    lat = ring_lattice(7, 3, 2)
    dev = resonator_device(lat, line_graph=True, omega0=1.0, J=0.5, ports={"1-0": 1.0},
                           frequencies={"0-1": 1.3}, hoppings={"0-1|1-2": 0.7})
    assert dev.ports == ("0-1",)
    k01, k12 = dev.resonators.index("0-1"), dev.resonators.index("1-2")
    assert dev.omega[k01] == 1.3
    h = dev.hamiltonian()
    assert h[k01, k12] == -0.7 and h[k12, k01] == -0.7
    # drawn disorder is reproducible from the seed, and differs between seeds
    a, b, c = (resonator_device(lat, omega0=1.0, ports={"0": 1.0}, sigma_omega=0.1, sigma_J=0.1, seed=s)
               for s in (1, 1, 2))
    assert np.array_equal(a.omega, b.omega) and np.array_equal(a.couplings, b.couplings)
    assert not np.array_equal(a.omega, c.omega)


@pytest.mark.parametrize("kwargs, message", [
    ({"ports": {"99": 1.0}}, "names no resonator"),
    ({"ports": {"0": 0.0}}, "must be positive"),
    ({"ports": {"0": float("nan")}}, "must be finite"),
    ({"ports": [("0", 1.0), ("0", 2.0)]}, "two ports"),
    ({"ports": {"0": 1.0}, "frequencies": {"77": 1.0}}, "names no resonator"),
    ({"ports": {"0": 1.0}, "hoppings": {"0|5": 1.0}}, "not coupled"),
    ({"ports": {"0": 1.0}, "hoppings": {"0-1": 1.0}}, "a coupling is named"),
    ({"ports": {"0": 1.0}, "sigma_omega": 0.1}, "needs a seed"),
    ({"ports": {"0": 1.0}, "kappa_int": -1.0}, "at least 0"),
    ({"ports": {"0": 1.0}, "sigma_J": float("nan")}, "finite"),
])
def test_bad_devices_are_refused_in_one_sentence(kwargs, message):
    with pytest.raises(ValueError, match=message) as exc:
        resonator_device(ring_lattice(7, 3, 2), **kwargs)
    assert "\n" not in str(exc.value)


def test_bad_frequencies_and_routes_are_refused():
    dev = resonator_device(ring_lattice(7, 3, 1), ports={"0": 1.0})
    for bad in ([np.nan], [], "1,2", [[1.0], [2.0, 3.0]]):
        with pytest.raises(ValueError):
            transmission(dev, bad)
    with pytest.raises(ValueError, match="internal loss"):
        transmission(dev, [0.0], method="chebyshev")
    level = float(np.linalg.eigvalsh(dev.hamiltonian().toarray())[0])
    with pytest.raises(ValueError, match="lossless"):
        transmission(dev, [level], method="direct")


def test_table_and_round_trip():
    tr = transmission(_device(), np.linspace(8.0, 12.0, 5))
    df = tr.to_dataframe()
    assert list(df.columns)[:4] == ["omega", "s21_re", "s21_im", "s21_abs2"]
    back = type(tr).from_dict(tr.as_dict())
    assert np.array_equal(back.s, tr.s) and back.resonators == tr.resonators


def test_ensemble_through_the_sweep(tmp_path):
    from hyperlattice.sweep import run_sweep
    from hyperlattice.sweep.device import merge_device

    grid = {"rings": 2, "ports": "0-1:0.1,30-31:0.1", "sigma_omega": 0.05, "sigma_J": 0.02, "seed": [1, 2, 3],
            "points": 40}
    run_sweep("device", grid, tmp_path / "ens", scheduler="serial", progress=False)
    (ens,) = merge_device(tmp_path / "ens")
    assert ens.realizations == 3 and ens.seeds == (1, 2, 3)
    # the same three devices built by hand
    lat = ring_lattice(7, 3, 2)
    w = np.linspace(-4.5, 2.5, 40)
    powers, levels = [], []
    for seed in (1, 2, 3):
        dev = resonator_device(lat, line_graph=True, kappa_int=0.05, ports={"0-1": 0.1, "30-31": 0.1},
                               sigma_omega=0.05, sigma_J=0.02, seed=seed)
        powers.append(transmission(dev, w).power)
        levels.append(np.linalg.eigvalsh(dev.hamiltonian().toarray()))
    assert np.allclose(ens.mean, np.mean(powers, axis=0), rtol=1e-12, atol=0)
    assert np.allclose(ens.level_spread, np.std(levels, axis=0, ddof=1), rtol=1e-9, atol=1e-14)
    with pytest.raises(ValueError, match="positive"):
        run_sweep("device", {"ports": "0-1:0"}, tmp_path / "bad", scheduler="serial", progress=False)
    from hyperlattice.sweep.tasks import _device_ports

    assert _device_ports("0-1@0.1+30-31@0.2") == _device_ports("0-1:0.1,30-31:0.2") == {"0-1": 0.1, "30-31": 0.2}


@pytest.mark.slow
def test_continuum_side_near_the_band_bottom():
    from hyperlattice.device import continuum_transmission

    lat = ring_lattice(7, 3, 4)
    w = np.array([-3.3, -3.1, -2.95])           # below the band bottom of -A (E0 = -2.88 at l = 4)
    cmp = continuum_transmission(lat, w, ports=("0", "30"), kappa_int=0.02, kappa_port=0.002)
    ratio = cmp.continuum / cmp.lattice
    assert np.all(np.abs(ratio - 1) < 0.25), ratio
    # units are the user's: omega0 = 7000, J = 66 shifts and stretches both sides alike
    cmp2 = continuum_transmission(lat, 7000 + 66 * w, ports=("0", "30"), omega0=7000.0, J=66.0,
                                  kappa_int=0.02 * 66, kappa_port=0.002 * 66)
    assert np.allclose(cmp2.continuum, cmp.continuum, rtol=1e-8)
    assert np.allclose(cmp2.lattice, cmp.lattice, rtol=1e-8)
    with pytest.raises(ValueError, match="kind 'sites'"):
        from hyperlattice.graph.lattice import line_graph

        continuum_transmission(line_graph(lat), w, ports=("0-1", "1-2"), kappa_int=0.1, kappa_port=0.01)


def test_auto_route_above_the_eigen_limit(monkeypatch):
    import importlib

    tm = importlib.import_module("hyperlattice.device.transmission")   # the module, not the function of that name

    dev = _device()
    w = np.linspace(8.0, 12.0, 1000)
    ref = transmission(dev, w)
    monkeypatch.setattr(tm, "EIGEN_MAX", 10)
    many = transmission(dev, w)                # many frequencies, with loss: the Chebyshev moments pay
    few = transmission(dev, w[:3])             # three frequencies: one LU each is cheaper
    assert (ref.method, many.method, few.method) == ("eigen", "chebyshev", "direct")
    assert np.max(np.abs(many.s - ref.s)) < 1e-10 and np.max(np.abs(few.s - ref.s[:3])) < 1e-10
