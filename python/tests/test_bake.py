"""bake and evaluate: the CLI's results, bit for bit; shapes and dtypes; bad input."""

import json

import numpy as np
import pytest

import medspheres
from conftest import flagged, without_clocks


def same_bits(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


def cli_bake(cli, mesh, out, *flags):
    cli("bake", mesh, "-o", out, "-q", *flags)
    return medspheres.load_spheres(out)


@pytest.mark.parametrize(
    "kwargs, flags",
    [
        ({"resolution": 16}, ["--resolution", "16"]),
        ({"max_spheres": 20}, ["--max-spheres", "20"]),
        ({"resolution": 14, "dilate": True, "vertex_tolerance": "0.01L"},
         ["--resolution", "14", "--dilate", "--vertex-tolerance", "0.01L"]),
        ({"method": "cover", "max_spheres": 24}, ["--method", "cover", "--max-spheres", "24"]),
        ({"method": "cover", "max_spheres": 6, "protrusion_allowance": 0.0,
          "protrusion_restarts": 2, "balance_rounds": 40},
         ["--method", "cover", "--max-spheres", "6", "--protrusion-allowance", "0",
          "--protrusion-restarts", "2", "--balance-rounds", "40"]),
        ({"resolution": 16, "solid": "robust", "robust_resolution": 32},
         ["--resolution", "16", "--solid", "robust", "--robust-resolution", "32"]),
    ],
)
def test_bake_equals_cli(cli, eight, tmp_path, kwargs, flags):
    ours = medspheres.bake(eight, **kwargs)
    theirs = cli_bake(cli, eight, tmp_path / "cli.json", *flags)
    assert len(ours) == len(theirs) > 0
    assert same_bits(ours.spheres, theirs.spheres)
    # the statistics too, but for the clocks
    assert without_clocks(ours.stats) == without_clocks(theirs.stats)
    assert ours.metadata["source"] == theirs.metadata["source"]
    assert ours.metadata["generator"]["params"] == theirs.metadata["generator"]["params"]


def test_bake_from_arrays_equals_bake_from_file(eight):
    vertices, triangles = medspheres.load_mesh(eight)
    assert vertices.dtype == np.float64 and vertices.shape[1] == 3
    assert triangles.dtype == np.int32 and triangles.shape == (634, 3)
    from_file = medspheres.bake(eight, resolution=16)
    from_arrays = medspheres.bake((vertices, triangles), resolution=16, name="eight")
    assert same_bits(from_file.spheres, from_arrays.spheres)
    assert from_arrays.metadata["source"]["mesh"] == "eight"
    # a list of lists is an array too
    assert same_bits(medspheres.bake((vertices.tolist(), triangles.tolist()), resolution=16).spheres,
                     from_file.spheres)
    # a reversed winding is oriented as a file's is, with the loader's warning (the corners
    # then come in another order, so the rounding may differ)
    with pytest.warns(UserWarning, match="flipped 1 inward-wound closed component"):
        flipped = medspheres.bake((vertices, triangles[:, ::-1]), resolution=16)
    assert flipped.spheres.shape == from_file.spheres.shape
    assert np.allclose(flipped.spheres, from_file.spheres, rtol=0, atol=1e-12)


def test_spheres_array_is_a_view(eight):
    s = medspheres.bake(eight, resolution=12)
    a, b = s.spheres, s.spheres
    assert a.shape == (len(s), 4) and a.dtype == np.float64
    assert not a.flags.owndata and not a.flags.writeable
    assert np.shares_memory(a, b)  # both views of the set's own memory
    assert (a[:, 3] > 0).all()
    del s
    assert np.isfinite(a).all()  # the view keeps the set alive


def test_sphere_set_from_array_round_trips(tmp_path):
    rng = np.random.default_rng(3)
    balls = np.column_stack([rng.normal(size=(50, 3)), rng.uniform(0.01, 1, 50)])
    s = medspheres.SphereSet(balls, {"note": "random"})
    assert same_bits(s.spheres, balls)
    s.save(tmp_path / "r.json")
    back = medspheres.load_spheres(tmp_path / "r.json")
    assert same_bits(back.spheres, balls)
    assert back.metadata == {"note": "random"}
    assert json.loads(s.to_json())["spheres"][7] == balls[7].tolist()
    assert repr(s) == "<medspheres.SphereSet of 50 spheres>"
    assert repr(medspheres.SphereSet(balls[:1])) == "<medspheres.SphereSet of 1 sphere>"


def test_evaluate_equals_cli(cli, eight, tmp_path):
    spheres = tmp_path / "s.json"
    cli("bake", eight, "-o", spheres, "-q", "--resolution", "16")
    flags = ["--samples", "20000", "--surface-samples", "3000", "--seed", "7"]
    theirs = json.loads(cli("eval", eight, spheres, "--json", *flags).stdout)
    ours = medspheres.evaluate(eight, spheres, samples=20000, surface_samples=3000, seed=7)
    assert without_clocks(ours) == without_clocks(theirs)
    # the same set given as a SphereSet or as an array
    s = medspheres.load_spheres(spheres)
    for given in (s, np.array(s.spheres)):
        again = medspheres.evaluate(eight, given, samples=20000, surface_samples=3000, seed=7)
        assert again["nerr"] == theirs["nerr"]
        assert again["mc_error"] == theirs["mc_error"]


@pytest.mark.parametrize(
    "kwargs, flags",
    [
        ({"max_spheres": 0}, ["--max-spheres", "0"]),
        ({"max_spheres": -3}, ["--max-spheres", "-3"]),
        ({"resolution": 1}, ["--resolution", "1"]),
        ({"object_angle": 4.0}, ["--object-angle", "4"]),
        ({"target_error": 1.5}, ["--target-error", "1.5"]),
        ({"vertex_tolerance": "abc", "dilate": True}, ["--vertex-tolerance", "abc", "--dilate"]),
        ({"method": "cover"}, ["--method", "cover"]),
        ({"threads": 5000}, ["--threads", "5000"]),
    ],
)
def test_bad_bake_options_raise_the_clis_message(cli, eight, tmp_path, kwargs, flags):
    r = cli("bake", eight, "-o", tmp_path / "x.json", *flags, check=False)
    assert r.returncode == 2
    prefix = "medspheres: error: "
    assert r.stderr.startswith(prefix)
    with pytest.raises(ValueError) as info:
        medspheres.bake(eight, **kwargs)
    assert isinstance(info.value, medspheres.InputError)
    assert str(info.value) == flagged(r.stderr[len(prefix):].strip())
    assert info.value.field in kwargs


def test_bad_meshes_raise(cli, tmp_path):
    missing = tmp_path / "none.stl"
    r = cli("bake", missing, "-o", tmp_path / "x.json", check=False)
    with pytest.raises(medspheres.InputError) as info:
        medspheres.bake(missing)
    assert info.value.kind == "file_missing"
    assert "medspheres: error: " + str(info.value) == r.stderr.strip()
    with pytest.raises(ValueError):
        medspheres.bake((np.zeros((3, 2)), np.zeros((1, 3), int)))
    with pytest.raises(ValueError):
        medspheres.bake((np.zeros((3, 3)), [[0, 1, 7]]))  # index out of range
    with pytest.raises(ValueError):
        medspheres.SphereSet(np.array([[0, 0, 0, -1.0]]))
    with pytest.raises(ValueError):
        medspheres.SphereSet(np.zeros((4, 3)))
    with pytest.raises(ValueError):
        medspheres.evaluate(missing, np.array([[0, 0, 0, 1.0]]), samples=0)


def test_cover_start_equals_cli_and_takes_arrays(cli, eight, tmp_path):
    start = medspheres.bake(eight, max_spheres=4)
    start.save(tmp_path / "start.json")
    ours = medspheres.bake(eight, method="cover", cover_start=tmp_path / "start.json")
    theirs = cli_bake(cli, eight, tmp_path / "cli.json", "--method", "cover", "--cover-start",
                      tmp_path / "start.json")
    assert same_bits(ours.spheres, theirs.spheres)
    assert ours.metadata["generator"]["params"] == {"mode": "cover_tighten", "budget": 4.0}
    assert ours.stats["certified"] is True and 1 <= len(ours) <= 4
    # an n x 4 array and a SphereSet start the same cover
    assert same_bits(medspheres.bake(eight, method="cover", cover_start=start.spheres).spheres,
                     ours.spheres)
    assert same_bits(medspheres.bake(eight, method="cover", cover_start=start).spheres,
                     ours.spheres)
    with pytest.raises(medspheres.InputError, match="max_spheres"):
        medspheres.bake(eight, method="cover", max_spheres=4, cover_start=start)
