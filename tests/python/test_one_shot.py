"""Every one-shot function and Session method on small meshes, against what is known
analytically or by construction."""
import numpy as np
import pytest

import locus


def test_geodesic_on_the_sphere_is_the_great_circle(sphere):
    V, F = sphere
    d = locus.geodesic_distance(V, F, 0)
    arc = np.arccos(np.clip(V @ V[0], -1, 1))
    assert abs(d[0]) == 0 and np.max(np.abs(d - arc)) < 0.06  # heat method at t = h^2, 642 vertices
    lm = locus.logmap(V, F, 0, 0.2)
    assert lm.patch[0] == 0 and len(lm.patch) == round(0.2 * len(V))
    assert np.allclose(np.hypot(lm.u, lm.v), lm.distance, rtol=1e-12)
    assert np.max(np.abs(lm.distance - arc[lm.patch])) < 0.06


def test_diffusion_pipelines(sphere):
    V, F = sphere
    gens = [0, 100, 200, 300]
    vor = locus.voronoi(V, F, gens)
    assert vor.labels.shape == (len(V),) and [vor.labels[g] for g in gens] == [0, 1, 2, 3]
    assert vor.points.shape[1] == 3 and vor.line_offsets[-1] == len(vor.line_points)
    w = locus.skinning_weights(V, F, gens)
    assert w.shape == (len(V), 4) and np.allclose(w.sum(axis=1), 1) and np.allclose(w[gens], np.eye(4))
    nn = locus.natural_neighbor_coordinates(V, F, gens, 100)
    assert nn.at_site and np.array_equal(nn.weights, [0, 1, 0, 0])
    s = locus.Session(V, F)
    field = s.prepare_natural_neighbors(gens)
    q = field.coordinates(([7], [[0.2, 0.3, 0.5]]))
    assert field.num_sites == 4 and np.isclose(q.weights.sum(), 1) and np.all(q.weights >= 0)
    adf = locus.adf(V, F, [1, 2, 3])
    hks = locus.hks(V, F, [1.0, 10.0], [1, 2, 3], method="selected_inversion")
    assert hks.shape == (3, 2) and np.allclose(hks[:, 0], adf, rtol=1e-10) and np.all(hks[:, 1] < hks[:, 0])
    assert np.allclose(s.auto_diffusion()[[1, 2, 3]], adf, rtol=0, atol=0)
    h = locus.heat_values(V, F, [0, 5], [0, 5, 9])
    e = locus.heat_exchange(V, F, [0, 5], [0, 5, 9])
    assert h.shape == (2, 3) and np.allclose(h.sum(axis=0), e, rtol=1e-12)
    faces, bary = s.random_points(10, seed=3)
    assert faces.shape == (10,) and np.allclose(bary.sum(axis=1), 1)
    assert s.voronoi((faces, bary)).labels.max() <= 9


def test_cvt(sphere):
    V, F = sphere
    sites, RV, RF, labels = locus.cvt(V, F, 40, iterations=3, seed=2)
    assert sites.shape == (40, 3) and labels.shape == (len(V),) and set(labels) <= set(range(40))
    assert RF.shape[1] == 3 and RV.shape[0] >= 40
    assert np.allclose(np.linalg.norm(RV, axis=1), 1, atol=0.05)  # on the sphere
    r = locus.Session(V, F).cvt(40, 3, 2)
    assert not r.remeshed and np.array_equal(r.labels, labels)


def test_deform_moves_the_handle_only_inside_the_roi(sphere):
    V, F = sphere
    s = locus.Session(V, F)
    r = s.deform(0, 0, [0, 0, 0.3], roi_fraction=0.2, handle_ring=0)
    moved = np.flatnonzero(np.any(r.V != V, axis=1))
    assert np.allclose(r.V[0] - V[0], [0, 0, 0.3]) and 0 < len(moved) <= r.roi_size == round(0.2 * len(V))
    assert np.array_equal(locus.deform(V, F, 0, 0, (0, 0, 0.3), roi_fraction=0.2, handle_ring=0), r.V)


def test_parameterizations_and_chapter_two(sphere):
    V, F = sphere
    p = locus.param(V, F, 0, 0.1, boundary="circle")
    assert p.uv.shape == (len(p.vertices), 2) and np.all(np.hypot(*p.uv.T) <= 1 + 1e-9) and p.flipped_faces == 0
    # A disk: the upper cap of the sphere, re-indexed.
    keep = np.all(V[F][:, :, 2] > 0.3, axis=1)
    used = np.unique(F[keep])
    index = -np.ones(len(V), int)
    index[used] = np.arange(len(used))
    DV, DF = V[used], index[F[keep]]
    disk = locus.Session(DV, DF).parameterize_disk()
    assert disk.converged and disk.flipped_faces == 0 and np.all(np.hypot(*disk.uv.T) <= 1 + 1e-9)
    pl = locus.perfect_laplacian(DV, DF, max_iterations=20)
    assert pl.edges.shape == (len(pl.weights), 2) and np.isclose(np.linalg.norm(pl.weights), 1)
    ss = locus.self_supporting(DV, DF, max_iterations=20)
    assert ss.V.shape == DV.shape and np.all(ss.forces >= 0)


def test_files_and_preview(sphere, tmp_path):
    V, F = sphere
    locus.write_mesh(str(tmp_path / "s.ply"), V, F, {"height": V[:, 2]})
    V2, F2 = locus.read_mesh(str(tmp_path / "s.ply"))
    assert np.array_equal(V2, V) and np.array_equal(F2, F)
    img = locus.render_preview(V, F, V[:, 2], width=64, height=48, path=str(tmp_path / "s.png"))
    assert img.shape == (48, 64, 3) and img.dtype == np.uint8 and img.std() > 0
    assert (tmp_path / "s.png").read_bytes()[:4] == b"\x89PNG"
    with pytest.raises(ValueError):
        locus.render_preview(V, F, V[:, 2], coloring="rainbow")
    SV, SF = locus.subdivide(V, F, 1)
    assert len(SF) == 4 * len(F) and len(SV) == len(V) + len(locus.Session(V, F).perfect_laplacian(max_iterations=1).edges)


def test_docstrings_state_units_and_defaults():
    doc = locus.Session.geodesic_distance.__doc__
    assert "t_factor=None" in doc and "4 on triangle meshes" in doc and "units of the positions" in doc and "threads" in doc
    assert "radians" in locus.logmap.__doc__ and "default 0.05" in locus.logmap.__doc__
