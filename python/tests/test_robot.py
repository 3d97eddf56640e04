"""bake_robot: the robot command's arrays and files."""

import numpy as np
import pytest

import medspheres

PLANNER_FILES = ["arm.curobo.yml", "arm.xrdf", "arm.spherized.urdf", "arm.srdf", "arm.foam.json"]


def test_bake_robot_equals_cli(cli, arm, tmp_path):
    ours_dir, theirs_dir = tmp_path / "py", tmp_path / "cli"
    baked = medspheres.bake_robot(arm, ours_dir, spheres_per_link=6, jobs=2)
    cli("robot", arm, "-o", theirs_dir, "--spheres-per-link", "6", "-q", "--jobs", "1")
    for name in PLANNER_FILES:
        assert (ours_dir / name).read_bytes() == (theirs_dir / name).read_bytes(), name
    sph = sorted(p.name for p in (theirs_dir / "sph").iterdir())
    assert sorted(p.name for p in (ours_dir / "sph").iterdir()) == sph
    for name in sph:
        assert (ours_dir / "sph" / name).read_bytes() == (theirs_dir / "sph" / name).read_bytes()

    assert list(baked.links) == ["base", "upper", "hand"]
    for which in ("inner", "outer"):
        doc = medspheres.load(theirs_dir / "arm.robot.json", set=which)
        assert doc.is_robot_file and doc.robot_name == "arm"
        for link, spheres in doc.links.items():
            ours = baked.links[link][which]
            assert ours.dtype == np.float64 and ours.shape == spheres.shape
            assert ours.tobytes() == spheres.tobytes(), (link, which)
    rows = {r["link"]: r for r in baked.stats}
    assert rows["upper"]["spheres"] <= 6 and rows["upper"]["outer_certified"]
    assert rows["hand"]["primitive_spheres"] == 1


def test_bake_robot_without_output_and_save(arm, tmp_path):
    baked = medspheres.bake_robot(arm, spheres_per_link=4, outer=False, formats=["curobo"])
    assert all(len(sets["outer"]) == 0 for sets in baked.links.values())
    assert baked.links["upper"]["inner"].shape[1] == 4
    baked.save(tmp_path / "out", formats=["curobo"], set="inner")
    assert [p.name for p in (tmp_path / "out").iterdir()] == ["arm.curobo.yml"]
    doc = medspheres.load(tmp_path / "out" / "arm.curobo.yml")
    assert np.array_equal(doc.links["upper"], baked.links["upper"]["inner"])


@pytest.mark.parametrize(
    "kwargs, flags",
    [
        ({"spheres_per_link": 0}, ["--spheres-per-link", "0"]),
        ({"budget": -1}, ["--budget", "-1"]),
        ({"links": {"upper": 0}}, ["--link", "upper=0"]),
        ({"formats": ["spheres"]}, ["--format", "spheres"]),
        ({"set": "both"}, ["--set", "both"]),
        ({"links": {"nope": 3}}, ["--link", "nope=3"]),
    ],
)
def test_bad_robot_options_raise_the_clis_message(cli, arm, tmp_path, kwargs, flags):
    import re

    r = cli("robot", arm, "-o", tmp_path / "o", "-q", *flags, check=False)
    assert r.returncode == 2
    expected = re.sub(r"--([a-z][a-z-]*)", lambda m: m.group(1).replace("-", "_"),
                      r.stderr.removeprefix("medspheres: error: ").strip())
    with pytest.raises(medspheres.InputError) as info:
        medspheres.bake_robot(arm, tmp_path / "o", **kwargs)
    assert str(info.value) == expected
    assert not (tmp_path / "o").exists()
