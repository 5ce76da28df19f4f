"""What every call of the package shares (python/src/module.cpp): the `threads` argument and
the checks of counts, indices, seeds and arrays from Python."""

import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import voroclip

SQUARE = [[(0, 0), (1, 0), (1, 1), (0, 1)]]
CUBE_V = np.array([(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=float)
CUBE_T = np.array([
    (0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
    (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)])


def threads_calls():
    """(name, f(threads) -> a tuple of arrays) for every call that takes `threads`."""
    rng = np.random.default_rng(4)
    s2, s3 = rng.random((40, 2)), rng.random((40, 3))
    cube = voroclip.domain3((CUBE_V, CUBE_T))
    tets = voroclip.Delaunay3(s3).simplices
    return [
        ("Delaunay2", lambda t: (voroclip.Delaunay2(s2, threads=t).simplices,)),
        ("Delaunay3", lambda t: (voroclip.Delaunay3(s3, threads=t).simplices,)),
        ("clip2d", lambda t: (voroclip.clip2d(SQUARE, s2, threads=t).energies,)),
        ("clip3d", lambda t: (voroclip.clip3d(cube, s3, threads=t).energies,)),
        ("random_points", lambda t: (voroclip.random_points(cube, 10, threads=t),)),
        ("cvt2d", lambda t: (voroclip.cvt2d(SQUARE, s2, iterations=3, threads=t).sites,)),
        ("cvt3d", lambda t: (voroclip.cvt3d(cube, s3, iterations=3, threads=t).sites,)),
        ("mesh2d", lambda t: (voroclip.mesh2d(SQUARE, vertices=30, threads=t).points,)),
        ("mesh3d", lambda t: (voroclip.mesh3d(cube, vertices=60, threads=t).points,)),
        ("quality", lambda t: (voroclip.quality(s3, tets, threads=t).q1,)),
    ]


def test_regression_threads_beyond_the_cores_run_on_the_cores():
    # threads=100000 crashed in tbb::task_arena (threads=50000 did not); any count above the
    # cores printed "TBB Warning: The number of workers is currently limited to ...". A
    # count is now clamped to the cores TBB may use: the same bits as threads=1, no warning.
    # A child process, so that a crash fails this test and not the whole run.
    code = textwrap.dedent("""
        import numpy as np, voroclip
        from test_module import threads_calls
        for name, f in threads_calls():
            one = f(1)
            for t in (3, 100000, 2**70, np.int64(7)):
                assert all(np.array_equal(a, b) for a, b in zip(one, f(t))), (name, t)
            print(name)
        """)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [os.path.dirname(os.path.dirname(voroclip.__file__)), os.path.dirname(__file__)]))
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == [name for name, _ in threads_calls()]
    assert "TBB" not in r.stderr, r.stderr


def test_negative_threads_raise_for_every_call():
    for name, f in threads_calls():
        with pytest.raises(voroclip.Error, match=r"^threads: expected 0 or None \(all cores\) "
                                                 r"or a count >= 1, got -1$"):
            f(-1)
        f(0)  # all cores
    with pytest.raises(voroclip.Error, match="^threads: expected an integer, got str 'two'$"):
        voroclip._core.Delaunay2(np.random.default_rng(1).random((5, 2)), "two")


def test_regression_bad_counts_seeds_and_arrays_raise_error():
    # These raised pybind11's TypeError "incompatible function arguments" with the C++
    # signatures (the C++ arguments were unsigned, or float64 arrays numpy could not make),
    # and mesh2d(vertices=-5) said "a value of the wrong type (<class 'int'>)"; the README
    # promises voroclip.Error, naming the argument and the value.
    rng = np.random.default_rng(6)
    s2 = rng.random((10, 2))
    cube = voroclip.domain3((CUBE_V, CUBE_T))
    words = [["a", "b"], ["c", "d"], ["e", "f"]]
    u32, u64 = r"\[0, 2\^32 - 1\]", r"\[0, 2\^64 - 1\]"
    cases = [
        (lambda: voroclip.cvt2d(SQUARE, s2, iterations=-1),
         rf"iterations: expected an integer in {u32}, got -1"),
        (lambda: voroclip.cvt3d(cube, s2[:, [0, 1, 1]], iterations=2**32),
         rf"iterations: expected an integer in {u32}, got 4294967296"),
        (lambda: voroclip.cvt2d(SQUARE, s2, method=3),
         "method: expected 'lbfgs' or 'lloyd', got 3"),
        (lambda: voroclip.random_points(cube, -3), rf"n: expected an integer in {u32}, got -3"),
        (lambda: voroclip.random_points(cube, 3, seed=-1),
         rf"seed: expected an integer in {u64}, got -1"),
        (lambda: voroclip.random_points(cube, 3, seed=2**64),
         rf"seed: expected an integer in {u64}, got 18446744073709551616"),
        (lambda: voroclip.mesh2d(SQUARE, vertices=-5),
         rf"mesh2d: option 'vertices': expected an integer in {u32}, got -5"),
        (lambda: voroclip.mesh2d(SQUARE, vertices=100.0),
         "mesh2d: option 'vertices': expected an integer, got float 100.0"),
        (lambda: voroclip.mesh2d(SQUARE, vertices=50, method="newton"),
         "mesh2d: option 'method': expected 'lbfgs' or 'lloyd', got 'newton'"),
        (lambda: voroclip.mesh3d(cube, vertices=50, max_topology_rounds=-1),
         rf"mesh3d: option 'max_topology_rounds': expected an integer in {u32}, got -1"),
        (lambda: voroclip.Delaunay2(words),
         r"points: expected an array of numbers, got list \[\['a', 'b'\], .*\] "
         r"\(could not convert string to float: 'a'\)"),
        (lambda: voroclip.Delaunay3([[1, 2, 3], [4, 5]]),
         r"points: expected an array of numbers, got list \[\[1, 2, 3\], \[4, 5\]\] "
         r"\(setting an array element with a sequence.*\)"),
        (lambda: voroclip.orient2d(words, [0, 0], [1, 1]),
         r"a: expected an array of numbers, got list .*"),
        (lambda: voroclip.domain2(SQUARE).locate(words),
         r"points: expected an array of numbers, got list .*"),
        (lambda: voroclip.clip2d(SQUARE, s2, density=(words, (0, 0), (1, 1))),
         r"density: the grid's values: expected an array of numbers, got list .*"),
    ]
    for call, message in cases:
        with pytest.raises(voroclip.Error, match=f"^{message}$"):
            call()
    # The edges of the ranges, and numpy integers, are taken.
    assert voroclip.random_points(cube, np.uint8(0)).shape == (0, 3)
    top = voroclip.random_points(cube, 2, seed=2**64 - 1)
    assert np.array_equal(top, voroclip.random_points(cube, 2, seed=np.uint64(2**64 - 1)))
    assert not np.array_equal(top, voroclip.random_points(cube, 2, seed=0))


def test_domains_and_error_have_docstrings():
    # Domain2, Domain3 and Error had no docstrings (None): what they are, how to build one,
    # their main methods.
    for cls, build, methods in ((voroclip.Domain2, "voroclip.domain2(", ("ring", "is_hole",
                                                                        "locate", "read")),
                                (voroclip.Domain3, "voroclip.domain3(", ("surface", "locate",
                                                                        "read"))):
        doc = cls.__doc__
        assert doc and doc.startswith("A validated ") and build in doc
        for name in methods:
            assert name + "(" in doc and getattr(cls, name).__doc__.count("\n") >= 2, name
    assert "A ValueError" in voroclip.Error.__doc__
    assert issubclass(voroclip.Error, ValueError)
