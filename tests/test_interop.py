"""networkx export of lattices and clusters: plain attributes, float positions, GraphML round trip."""

import networkx as nx
import numpy as np
import pytest

import hyperlattice as hl
from hyperlattice.graph.clusters import pbc_cluster
from hyperlattice.graph.lattice import lattice_from_networkx, line_graph, ring_lattice


@pytest.mark.parametrize("lat", [ring_lattice(7, 3, 3), ring_lattice(4, 5, 2), line_graph(ring_lattice(7, 3, 2))],
                         ids=["73", "45", "line"])
def test_lattice_graphml_round_trip(lat, tmp_path):
    g = lat.to_networkx()
    x, y = g.nodes[5]["pos"]
    assert isinstance(x, float) and complex(x, y) == lat.z[5]
    # every attribute is a plain number or string (GraphML) once pos is left out
    path = tmp_path / "lat.graphml"
    nx.write_graphml(lat.to_networkx(pos=False), path)
    back = lattice_from_networkx(nx.read_graphml(path))
    assert back.sites == lat.sites and back.kind == lat.kind
    np.testing.assert_array_equal(back.z, lat.z)
    np.testing.assert_array_equal(back.edges, lat.edges)
    # and directly, without the file
    assert lattice_from_networkx(g).sites == lat.sites
    assert hl.lattice_from_networkx is lattice_from_networkx


def test_lattice_from_a_rewired_graph_is_refused():
    g = ring_lattice(7, 3, 2).to_networkx()
    u, v = next(iter(g.edges))
    g.remove_edge(u, v)
    g.add_edge(u, (v + 3) % g.number_of_nodes())
    with pytest.raises(ValueError, match="edges differ"):
        lattice_from_networkx(g)
    g2 = ring_lattice(7, 3, 2).to_networkx()
    g2.nodes[0]["x"] += 1e-6
    with pytest.raises(ValueError, match="positions differ"):
        lattice_from_networkx(g2)
    with pytest.raises(ValueError, match="networkx graph"):
        lattice_from_networkx([1, 2])


def test_cluster_graphml_round_trip(tmp_path):
    c = pbc_cluster(8, 3, "bolza")
    g = c.to_networkx()
    assert g.number_of_nodes() == c.sites and g.number_of_edges() == c.n_edges
    path = tmp_path / "c.graphml"
    nx.write_graphml(g, path)
    back = nx.read_graphml(path, node_type=int)
    assert back.graph["genus"] == c.genus and back.graph["name"] == c.name
    # the rotation system survives: rebuild the neighbour table from the slots
    nb = np.full((c.sites, c.q), -1)
    for u, v, d in back.edges(data=True):
        a, b = min(u, v), max(u, v)
        nb[a, d["slot_u"]] = b
        nb[b, d["slot_v"]] = a
    np.testing.assert_array_equal(nb, c.neighbours)


def test_sweep_table_to_dataframe(monkeypatch):
    """A sweep's table goes to pandas the same way as a result's (issue 21)."""
    pd = pytest.importorskip("pandas")
    from hyperlattice.sweep.store import SweepTable

    table = SweepTable(columns={"W": np.array([1.0, 2.0]), "r_count": np.array([3, 4]), "model": ["box", "box"]},
                       metadata={"task": "disorder"})
    df = table.to_dataframe()
    assert isinstance(df, pd.DataFrame) and list(df.columns) == ["W", "r_count", "model"]
    np.testing.assert_array_equal(df["W"].to_numpy(), [1.0, 2.0])
    assert df["model"].tolist() == ["box", "box"] and df.attrs["hyperlattice"] == {"task": "disorder"}
    assert SweepTable.to_pandas is SweepTable.to_dataframe

    import importlib

    real = importlib.import_module

    def without_pandas(name, *args):
        if name == "pandas":
            raise ImportError(f"No module named {name!r}")
        return real(name, *args)

    monkeypatch.setattr(importlib, "import_module", without_pandas)
    with pytest.raises(ImportError, match=r'^this export needs pandas, which is not installed: pip install "hyperlattice\[pandas\]"\.$'):
        table.to_dataframe()
