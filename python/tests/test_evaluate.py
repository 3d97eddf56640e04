"""evaluate and evaluate_robot: the CLI's eval, figure for figure; the solid measured; lengths."""

import json

import numpy as np
import pytest

import medspheres
from conftest import flagged, without_clocks, write_arm

FAST = {"samples": 20000, "surface_samples": 2000, "seed": 5}
FAST_FLAGS = ["--samples", "20000", "--surface-samples", "2000", "--seed", "5"]


@pytest.fixture(scope="module")
def robust_set(cli, eight, tmp_path_factory):
    """eight.off baked from its robust solid at resolution 24: the file records that solid."""
    path = tmp_path_factory.mktemp("robust") / "eight.robust.json"
    cli("bake", eight, "-o", path, "-q", "--resolution", "14", "--solid", "robust",
        "--robust-resolution", "24")
    return path


def test_evaluate_measures_the_recorded_solid_as_the_cli_does(cli, eight, robust_set):
    theirs = json.loads(cli("eval", eight, robust_set, "--json", *FAST_FLAGS).stdout)
    assert theirs["solid"] == "robust" and theirs["robust_resolution"] == 24
    ours = medspheres.evaluate(eight, robust_set, **FAST)
    assert without_clocks(ours) == without_clocks(theirs)
    # a SphereSet carries its record too; an array records nothing: the winding solid
    from_set = medspheres.evaluate(eight, medspheres.load_spheres(robust_set), **FAST)
    assert from_set["solid"] == "robust" and from_set["mesh_volume"] == theirs["mesh_volume"]
    array = np.array(medspheres.load_spheres(robust_set).spheres)
    winding = medspheres.evaluate(eight, array, **FAST)
    assert winding["solid"] == "winding" and "robust_resolution" not in winding
    # the robust solid holds the mesh: more volume; its spheres lie inside it, exactly
    # measured, but stick out of the mesh's own solid (nerr only a lower bound there)
    assert theirs["mesh_volume"] > winding["mesh_volume"]
    assert theirs["nerr_kind"] == "exact" and theirs["max_protrusion"] <= 0
    assert winding["nerr_kind"] == "lower_bound" and winding["max_protrusion"] > 0


@pytest.mark.parametrize(
    "kwargs, flags",
    [
        ({"solid": "winding"}, ["--solid", "winding"]),
        # robust without options of its own: the options the file records (resolution 24)
        ({"solid": "robust"}, ["--solid", "robust"]),
        ({"solid": "robust", "robust_resolution": 28}, ["--solid", "robust",
                                                        "--robust-resolution", "28"]),
        ({"solid": "robust", "robust_resolution": 28, "robust_thickness": "0.01L"},
         ["--solid", "robust", "--robust-resolution", "28", "--robust-thickness", "0.01L"]),
    ],
)
def test_evaluate_solid_options_equal_cli(cli, eight, robust_set, kwargs, flags):
    theirs = json.loads(cli("eval", eight, robust_set, "--json", *FAST_FLAGS, *flags).stdout)
    ours = medspheres.evaluate(eight, robust_set, **FAST, **kwargs)
    assert without_clocks(ours) == without_clocks(theirs)
    assert ours["solid"] == kwargs["solid"]
    if kwargs["solid"] == "robust":
        assert ours["robust_resolution"] == kwargs.get("robust_resolution", 24)


def test_evaluate_robust_thickness_as_a_number(eight, robust_set):
    longest = medspheres.evaluate(eight, robust_set, **FAST)["bbox_largest_side"]
    as_text = medspheres.evaluate(eight, robust_set, **FAST, solid="robust",
                                  robust_resolution=28, robust_thickness="0.01L")
    for number in (0.01 * longest, np.float64(0.01 * longest)):
        as_number = medspheres.evaluate(eight, robust_set, **FAST, solid="robust",
                                        robust_resolution=28, robust_thickness=number)
        assert as_number["robust_thickness"] == 0.01 * longest
        assert without_clocks(as_number) == without_clocks(as_text)


@pytest.mark.parametrize(
    "kwargs, flags",
    [
        ({"solid": "robst"}, ["--solid", "robst"]),
        ({"robust_thickness": "thin"}, ["--robust-thickness", "thin"]),
        ({"robust_thickness": -1.0}, ["--robust-thickness", "-1"]),
        ({"solid": "robust", "robust_resolution": 3}, ["--solid", "robust",
                                                       "--robust-resolution", "3"]),
    ],
)
def test_bad_solid_options_raise_the_clis_message(cli, eight, robust_set, kwargs, flags):
    r = cli("eval", eight, robust_set, *FAST_FLAGS, *flags, check=False)
    assert r.returncode == 2
    with pytest.raises(medspheres.InputError) as info:
        medspheres.evaluate(eight, robust_set, **FAST, **kwargs)
    assert str(info.value) == flagged(r.stderr.removeprefix("medspheres: error: ").strip())
    assert info.value.field in kwargs


def test_a_length_of_another_type_names_its_option(eight):
    for value in ([0.1], True, {"a": 1}):
        with pytest.raises(medspheres.InputError) as info:
            medspheres.evaluate(eight, np.array([[0, 0, 0, 0.1]]), robust_thickness=value)
        assert info.value.field == "robust_thickness"
        assert "must be a length" in str(info.value)


@pytest.fixture(scope="module")
def baked_arm(cli, tmp_path_factory):
    """The conftest arm, baked by the CLI with 4 spheres a link into its cuRobo file."""
    root = tmp_path_factory.mktemp("arm")
    urdf = write_arm(root)
    cli("robot", urdf, "-o", root / "out", "-q", "--spheres-per-link", "4", "--format",
        "curobo")
    return urdf, root / "out"


def test_evaluate_robot_equals_cli(cli, baked_arm):
    urdf, out = baked_arm
    yml = out / "arm.curobo.yml"
    theirs = json.loads(cli("eval", urdf, yml, "--json", *FAST_FLAGS).stdout)
    rows = medspheres.evaluate_robot(urdf, yml, **FAST)
    assert isinstance(rows, list) and all(isinstance(r, dict) for r in rows)
    assert rows == theirs["links"]
    assert [r["link"] for r in rows] == ["base", "upper", "hand"]
    # the cuRobo file carries the outer sets, certified covers: no sampled point is outside
    for r in rows:
        assert r["uncovered_max"] == 0.0, r["link"]
        assert r["surface_certificate"]["certified"], r["link"]
        assert r["max_protrusion"] > 0.0  # a cover sticks out
    assert rows[2]["primitives"] == 1  # the hand's sphere primitive, exact
    # the same spheres given as a dict of arrays, and as SphereSets
    doc = medspheres.load(yml)
    as_arrays = medspheres.evaluate_robot(urdf, dict(doc.links), **FAST)
    assert as_arrays == rows
    as_sets = medspheres.evaluate_robot(
        urdf, {k: medspheres.SphereSet(v) for k, v in doc.links.items()}, **FAST)
    assert as_sets == rows


def test_evaluate_robot_closed_form(baked_arm):
    """One ball inside the hand's box: nerr = 1 - ball / box, exactly."""
    urdf, _ = baked_arm
    rows = medspheres.evaluate_robot(urdf, {"hand": np.array([[0.0, 0.0, 0.0, 0.01]])}, **FAST)
    hand = rows[2]
    assert hand["spheres"] == 1 and hand["primitives"] == 0
    assert hand["nerr_kind"] == "exact"
    # the box's corners as the OBJ loader (assimp) reads them: in single precision
    half = np.float32([0.015, 0.015, 0.025]).astype(np.float64)
    box = np.prod(2 * half)
    assert hand["nerr"] == pytest.approx(1 - 4 / 3 * np.pi * 0.01**3 / box, rel=1e-9)
    assert hand["max_protrusion"] == pytest.approx(0.01 - half[0], rel=1e-9)
    assert rows[0]["note"] and "nerr" not in rows[0]


def test_evaluate_robot_bad_input(cli, baked_arm, eight, tmp_path):
    urdf, out = baked_arm
    # a link the robot lacks is not measured, and named in a warning
    ball = np.array([[0, 0, 0, 0.01]])
    with pytest.warns(UserWarning, match="link 'elbow' is not in the robot"):
        rows = medspheres.evaluate_robot(urdf, {"elbow": ball, "hand": ball}, **FAST)
    assert [r["link"] for r in rows] == ["base", "upper", "hand"]
    assert [r["spheres"] for r in rows] == [0, 0, 1]
    # spheres of no link of the robot: an error naming the link
    with pytest.raises(medspheres.InputError) as info:
        medspheres.evaluate_robot(urdf, {"elbow": ball})
    assert "'elbow'" in str(info.value)
    one = tmp_path / "one.json"
    medspheres.SphereSet(np.array([[0, 0, 0, 0.01]])).save(one)
    r = cli("eval", urdf, one, check=False)
    assert r.returncode == 2
    with pytest.raises(medspheres.InputError) as info:
        medspheres.evaluate_robot(urdf, one)
    assert "medspheres: error: " + str(info.value) == r.stderr.strip()
    with pytest.raises(medspheres.InputError) as info:
        medspheres.evaluate_robot(urdf, out / "arm.curobo.yml", samples=0)
    assert info.value.field == "samples"
    with pytest.raises(TypeError):
        medspheres.evaluate_robot(urdf, [np.zeros((1, 4))])


def test_evaluate_robot_packages(baked_arm, tmp_path):
    """package:// URIs resolve through `packages`, as the CLI's --package does."""
    urdf, _ = baked_arm
    text = urdf.read_text().replace('"meshes/hand.obj"', '"package://arm_pkg/meshes/hand.obj"')
    assert "package://" in text
    moved = tmp_path / "moved.urdf"
    moved.write_text(text.replace('"meshes/upper.obj"', f'"{urdf.parent}/meshes/upper.obj"'))
    ball = {"hand": np.array([[0.0, 0.0, 0.0, 0.01]])}
    with pytest.raises(medspheres.InputError):
        medspheres.evaluate_robot(moved, ball, **FAST)
    rows = medspheres.evaluate_robot(moved, ball, packages={"arm_pkg": str(urdf.parent)}, **FAST)
    assert rows == medspheres.evaluate_robot(urdf, ball, **FAST)
