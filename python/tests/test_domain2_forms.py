"""Domain2 forms: the command line's generators (annulus:, square-holes:) against closed
forms and the CLI, and the tags mesh2d gives several polygons, against exact location in
each polygon given alone."""

import math
import subprocess

import numpy as np
import pytest

import voroclip


def test_annulus_generator_matches_closed_form_and_method():
    d = voroclip.domain2("annulus:1,2,64")
    n = 64
    regular = 0.5 * n * math.sin(2 * math.pi / n)  # area of a regular n-gon of radius 1
    assert d.area == pytest.approx(regular * (4 - 1), rel=1e-14)
    assert d.nb_rings == 2 and not d.is_hole(0) and d.is_hole(1)
    m = voroclip.Domain2.annulus(1, 2, 64)
    np.testing.assert_array_equal(d.ring(0), m.ring(0))
    np.testing.assert_array_equal(d.ring(1), m.ring(1))
    # Vertex 0 of each circle at angle 0; every vertex on its circle.
    r0 = np.hypot(*d.ring(0).T)
    np.testing.assert_allclose(r0, 2, rtol=1e-15)
    assert voroclip.Domain2.annulus(1, 2).nb_rings == 2  # 64 segments by default
    assert len(voroclip.Domain2.annulus(1, 2).ring(0)) == 64


def test_square_holes_generator_matches_closed_form():
    d = voroclip.domain2("square-holes:3,0.5")
    assert d.nb_rings == 10
    assert d.area == pytest.approx(1 - 0.25, rel=1e-15)
    assert d.bounds == (0, 0, 1, 1)
    m = voroclip.Domain2.square_holes(3, 0.5)
    for r in range(10):
        np.testing.assert_array_equal(d.ring(r), m.ring(r))


@pytest.mark.parametrize("spec, message", [
    ("annulus:2,1,64", "annulus:R_IN,R_OUT,SEGMENTS needs 0 < R_IN < R_OUT and 3 <= SEGMENTS"),
    ("annulus:1,2", "annulus:R_IN,R_OUT,SEGMENTS: expected 3 comma-separated numbers, got '1,2'"),
    ("annulus:1,2,6.5", "needs 0 < R_IN < R_OUT and 3 <= SEGMENTS"),
    ("square-holes:0,0.5", "square-holes:K,FRACTION needs 1 <= K <= 1000 and 0 < FRACTION < 1"),
    ("square-holes:2,x", "expected 2 comma-separated numbers, got '2,x'"),
])
def test_generator_errors(spec, message):
    with pytest.raises(voroclip.Error, match=message.replace("(", r"\(").replace(")", r"\)")):
        voroclip.domain2(spec)


def test_generator_in_random_points_is_2d_and_matches_cli(cli, tmp_path):
    # A generator string is a 2D domain for random_points, and gives the CLI's
    # `cvt2d annulus:... --random` start sites bit for bit.
    pts = voroclip.random_points("annulus:1,2,64", 40, seed=5)
    assert pts.shape == (40, 2)
    out = tmp_path / "sites.txt"
    subprocess.run([cli, "-q", "cvt2d", "annulus:1,2,64", "--random", "40", "--seed", "5",
                    "--iterations", "0", "-o", str(out)], check=True)
    np.testing.assert_array_equal(pts, np.loadtxt(out))
    np.testing.assert_array_equal(pts, voroclip.random_points(voroclip.Domain2.annulus(1, 2, 64),
                                                              40, seed=5))


def _polygons():
    # Polygon 0: a square with a hole; polygon 1: a square with a hole to its right;
    # polygon 2: an island inside polygon 0's hole.
    return [
        [[(0, 0), (4, 0), (4, 4), (0, 4)], [(1, 1), (1, 3), (3, 3), (3, 1)]],
        [[(5, 0), (9, 0), (9, 4), (5, 4)], [(6, 1), (6, 2), (8, 2), (8, 1)]],
        [[(1.5, 1.5), (2.5, 1.5), (2.5, 2.5), (1.5, 2.5)]],
    ]


class _Shape:
    """A shapely-like polygon: .exterior and .interiors with .coords."""

    class _Ring:
        def __init__(self, coords):
            self.coords = coords

    def __init__(self, rings):
        self.exterior = self._Ring(rings[0])
        self.interiors = [self._Ring(r) for r in rings[1:]]


def test_several_polygons_tag_rings_and_regions(tmp_path):
    polygons = _polygons()
    rings = [r for p in polygons for r in p]
    alone = [voroclip.domain2([r]) for r in rings]  # each ring as a domain of its own
    expected_region = {0: 1, 1: 2, 2: 3}
    for form in ("shapes", "json"):
        if form == "shapes":
            domain = [_Shape(p) for p in polygons]
        else:
            path = tmp_path / "three.json"
            path.write_text(str([[list(map(list, r)) for r in p] for p in polygons]))
            domain = str(path)
        mesh = voroclip.mesh2d(domain, vertices=500, seed=2)
        xy = mesh.points
        # Triangles: the polygon holding the centroid, by exact location.
        cent = xy[mesh.cells].mean(axis=1)
        inside = [a.locate(cent) > 0 for a in alone]
        polygon = np.where(inside[4], 2, np.where(inside[0] & ~inside[1], 0,
                                                  np.where(inside[2] & ~inside[3], 1, -1)))
        assert (polygon >= 0).all()
        np.testing.assert_array_equal(mesh.cell_tags, [expected_region[p] for p in polygon])
        # Boundary edges: the ring both ends lie on (exactly: locate gives 0 on a ring).
        ends = xy[mesh.boundary_edges]
        for e, tag in enumerate(mesh.boundary_tags):
            on = [r for r in range(5) if (alone[r].locate(ends[e]) == 0).all()]
            assert on == [tag - 1], (form, e, ends[e], tag)
        assert sorted(set(mesh.boundary_tags.tolist())) == [1, 2, 3, 4, 5]
