"""bake_robot: the robot command's arrays and files."""

import numpy as np
import pytest

import medspheres
from conftest import flagged

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
    # cuRobo v2's configuration, v1's, and the spheres alone.
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == [
        "arm.curobo.yml", "arm.curobo_spheres.yml", "arm.curobo_v1.yml"]
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
        # lengths given as numbers are judged as their text is
        ({"dilate": True, "vertex_tolerance": -0.001}, ["--dilate", "--vertex-tolerance", "-0.001"]),
        ({"cover": 0}, ["--cover", "0"]),
        ({"dilate": True, "max_protrusion": float("nan")},
         ["--dilate", "--max-protrusion", "nan"]),
        ({"solid": "robst"}, ["--solid", "robst"]),
        ({"robust_thickness": -0.5}, ["--robust-thickness", "-0.5"]),
        ({"self_collision_samples": 0}, ["--self-collision-samples", "0"]),
        ({"self_collision_threshold": 1.5}, ["--self-collision-threshold", "1.5"]),
        ({"self_collision_margin": -0.01}, ["--self-collision-margin", "-0.01"]),
        ({"tool_frames": ["nope"]}, ["--tool-frame", "nope"]),
        ({"free_joints": ["nope"]}, ["--free-joint", "nope"]),
        ({"balance_rounds": -1}, ["--balance-rounds", "-1"]),
        ({"protrusion_allowance": -0.5}, ["--protrusion-allowance", "-0.5"]),
        ({"jobs": -1}, ["--jobs", "-1"]),
        ({"jobs": 2000}, ["--jobs", "2000"]),
    ],
)
def test_bad_robot_options_raise_the_clis_message(cli, arm, tmp_path, kwargs, flags):
    r = cli("robot", arm, "-o", tmp_path / "o", "-q", *flags, check=False)
    assert r.returncode == 2
    expected = flagged(r.stderr.removeprefix("medspheres: error: ").strip())
    with pytest.raises(medspheres.InputError) as info:
        medspheres.bake_robot(arm, tmp_path / "o", **kwargs)
    assert str(info.value) == expected
    assert not (tmp_path / "o").exists()


def test_an_output_folder_holding_an_input_is_refused_and_the_inputs_stay(cli, arm, tmp_path):
    # The folder is replaced as a whole: the URDF's own folder, or the folder of its meshes.
    mesh = tmp_path / "meshes" / "hand.obj"
    before = mesh.read_bytes()
    for out in (tmp_path, tmp_path / "meshes"):
        r = cli("robot", arm, "-o", out, "-q", check=False)
        assert r.returncode == 2
        assert "holds the input" in r.stderr
        with pytest.raises(medspheres.InputError) as info:
            medspheres.bake_robot(arm, out, spheres_per_link=4)
        assert str(info.value) == flagged(r.stderr.removeprefix("medspheres: error: ").strip())
        assert arm.exists() and mesh.read_bytes() == before
    baked = medspheres.bake_robot(arm, spheres_per_link=4, outer=False, measure=False)
    with pytest.raises(medspheres.InputError, match="holds the input"):
        baked.save(tmp_path / "meshes")
    assert mesh.read_bytes() == before


def rz(angle):
    c, s = np.cos(angle), np.sin(angle)
    x = np.eye(4)
    x[:2, :2] = [[c, -s], [s, c]]
    return x


def translate(v):
    x = np.eye(4)
    x[:3, 3] = v
    return x


def placed(balls, x):
    return np.column_stack([balls[:, :3] @ x[:3, :3].T + x[:3, 3], balls[:, 3]])


def gap(a, b):
    d = np.linalg.norm(a[:, None, :3] - b[None, :, :3], axis=2) - a[:, None, 3] - b[None, :, 3]
    return max(0.0, d.min())


def test_robot_bounds_against_brute_force(arm, tmp_path):
    baked = medspheres.bake_robot(arm, tmp_path / "out", spheres_per_link=6, formats=["robot"])
    robot = medspheres.RobotBounds(tmp_path / "out" / "arm.robot.json")
    assert robot.joint_names == ["j1"]
    obstacle = np.array([[0.0, 0.0, 0.0, 0.02], [0.01, 0.0, 0.0, 0.02]])
    for q in (0.0, 0.7):
        # the arm's forward kinematics, written out: base fixed, upper by j1, hand fixed on it
        poses = {"base": np.eye(4), "upper": translate([0, 0, 0.03]) @ rz(q)}
        poses["hand"] = poses["upper"] @ translate([0, 0, 0.12])
        sets = {link: {k: placed(v, poses[link]) for k, v in s.items()} for link, s in
                baked.links.items()}
        # self: only base and hand are not adjacent
        lower, upper, certified = robot.bounds([q])
        assert certified
        assert lower <= gap(sets["base"]["outer"], sets["hand"]["outer"]) <= lower + 1e-9
        assert upper - 1e-9 <= gap(sets["base"]["inner"], sets["hand"]["inner"]) <= upper
        # a scene object: its own balls on both sides
        x = translate([0.15, 0.0, 0.2])
        world = placed(obstacle, x)
        lower, upper, _ = robot.bounds([q], [(obstacle, x)], include_self=False)
        assert lower <= min(gap(s["outer"], world) for s in sets.values()) <= lower + 1e-9
        assert upper - 1e-9 <= min(gap(s["inner"], world) for s in sets.values()) <= upper
        verdict = robot.collide([q], [(obstacle, x)], include_self=False, margin=lower / 2)
        assert verdict["verdict"] == "free" and verdict["certified"]
    with pytest.raises(ValueError):
        robot.bounds([0.0, 1.0])  # one joint


def test_bake_robot_lengths_as_numbers_or_text(arm):
    """A number in metres gives the bits of its text; other types and bad values name the option."""
    common = {"spheres_per_link": 4, "outer": False, "measure": False, "dilate": True}
    as_text = medspheres.bake_robot(arm, **common, vertex_tolerance="0.002",
                                    max_protrusion="0.001")
    as_number = medspheres.bake_robot(arm, **common, vertex_tolerance=0.002,
                                      max_protrusion=np.float64(0.001))
    for link, sets in as_text.links.items():
        assert as_number.links[link]["inner"].tobytes() == sets["inner"].tobytes(), link
    # the dilation did something: the dilated sets are not the inner sets of a plain bake
    plain = medspheres.bake_robot(arm, spheres_per_link=4, outer=False, measure=False)
    assert any(plain.links[k]["inner"].tobytes() != v["inner"].tobytes()
               for k, v in as_text.links.items())
    for field, value in (("vertex_tolerance", [0.002]), ("max_protrusion", True),
                         ("cover", {"x": 1}), ("robust_thickness", b"0.1")):
        with pytest.raises(medspheres.InputError) as info:
            medspheres.bake_robot(arm, **{**common, field: value})
        assert info.value.field == field
        assert str(info.value).startswith(field + ": must be a length")



def test_robot_bounds_order_and_witnesses(arm, tmp_path):
    """An order's witnesses decide some collisions without a walk; no verdict changes."""
    medspheres.bake_robot(arm, tmp_path / "out", spheres_per_link=6, formats=["robot"])
    path = tmp_path / "out" / "arm.robot.json"
    plain = medspheres.RobotBounds(path)
    ordered = medspheres.RobotBounds(path, order_samples=200, order_margin=0.2, seed=3)
    assert plain.witnesses == 0
    assert ordered.witnesses >= 1
    by_witness = 0
    for q in np.linspace(-3.0, 3.0, 25):
        for margin in (0.0, 0.05, 0.2):
            a = plain.collide([q], margin=margin)
            b = ordered.collide([q], margin=margin)
            assert a["verdict"] == b["verdict"], (q, margin)
            assert not a["by_witness"]
            by_witness += b["by_witness"]
    assert by_witness > 0
    with pytest.raises(ValueError):
        medspheres.RobotBounds(path, order_samples=10, order_margin=-1.0)


def test_bake_robot_cover_start_equals_cli(cli, arm, tmp_path):
    # the start: the inner sets in cuRobo's format (link frames); they miss the surface
    cli("robot", arm, "-o", tmp_path / "inner", "--spheres-per-link", "5", "--no-outer", "-q")
    start = tmp_path / "inner" / "arm.curobo.yml"
    baked = medspheres.bake_robot(arm, tmp_path / "py", spheres_per_link=6, cover_start=start)
    cli("robot", arm, "-o", tmp_path / "cli", "--spheres-per-link", "6", "-q", "--cover-start", start)
    for name in PLANNER_FILES:
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    rows = {r["link"]: r for r in baked.stats}
    assert rows["upper"]["outer_certified"] and 1 <= rows["upper"]["outer_spheres"] <= 5
    # the same from a dict of arrays
    doc = medspheres.load(start)
    again = medspheres.bake_robot(arm, spheres_per_link=6, cover_start=dict(doc.links))
    assert np.array_equal(again.links["upper"]["outer"], baked.links["upper"]["outer"])
    # a link the robot lacks is named in a warning
    with pytest.warns(UserWarning, match="nope"):
        medspheres.bake_robot(arm, spheres_per_link=6,
                              cover_start={"nope": doc.links["upper"], **dict(doc.links)})


def test_bake_robot_cover_search_equals_cli(cli, arm, tmp_path):
    """The covering sets' search (allowance, restarts, balancing rounds) as the robot
    command's flags give it: the same files, and covers other than the default's."""
    search = {"protrusion_allowance": 0.0, "protrusion_restarts": 2, "balance_rounds": 40}
    baked = medspheres.bake_robot(arm, tmp_path / "py", spheres_per_link=6, **search)
    cli("robot", arm, "-o", tmp_path / "cli", "--spheres-per-link", "6", "-q",
        "--protrusion-allowance", "0", "--protrusion-restarts", "2", "--balance-rounds", "40")
    for name in PLANNER_FILES:
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    plain = medspheres.bake_robot(arm, spheres_per_link=6)
    assert all(r["outer_certified"] for r in baked.stats)
    assert any(baked.links[link]["outer"].tobytes() != plain.links[link]["outer"].tobytes()
               for link in baked.links)


def test_bake_robot_cover_search_without_covers_names_the_keywords(arm, tmp_path):
    """A cover search asked of a bake without covering sets names the keyword given and the
    one that leaves the covers out, as Python spells them, and writes nothing."""
    with pytest.raises(medspheres.InputError) as info:
        medspheres.bake_robot(arm, tmp_path / "o", outer=False, balance_rounds=4)
    message = str(info.value)
    assert "balance_rounds" in message and "outer=False" in message, message
    assert "no_outer" not in message, message
    assert not (tmp_path / "o").exists()


def test_bake_robot_planner_setup_equals_cli(cli, arm, tmp_path):
    """Tool frames, the self-collision matrix and the default configuration: the same files as
    the robot command's flags, and RobotBake.planner as the robot file's "planner"."""
    ours_dir, theirs_dir = tmp_path / "py", tmp_path / "cli"
    baked = medspheres.bake_robot(arm, ours_dir, spheres_per_link=6, tool_frames=["hand"],
                                  self_collision_samples=300, self_collision_seed=3)
    run = cli("robot", arm, "-o", theirs_dir, "--spheres-per-link", "6", "--tool-frame", "hand",
              "--self-collision-samples", "300", "--self-collision-seed", "3")
    for name in ["arm.curobo.yml", "arm.curobo_v1.yml", "arm.curobo_spheres.yml", "arm.xrdf",
                 "arm.srdf", "arm.self_collision.txt"]:
        assert (ours_dir / name).read_bytes() == (theirs_dir / name).read_bytes(), name
    planner = baked.planner
    assert planner["tool_frames"] == ["hand"] and planner["tool_frames_from"] == "option"
    matrix = planner["self_collision"]
    assert matrix["samples"] == 300 and matrix["seed"] == 3
    links = list(baked.links)
    # every pair of links with spheres once, [link1, link2, class, skipped]
    with_spheres = [l for l in links if len(baked.links[l]["outer"])]
    assert len(matrix["pairs"]) == len(with_spheres) * (len(with_spheres) - 1) // 2
    assert {p[2] for p in matrix["pairs"]} <= {"adjacent", "always", "never", "sphere_only",
                                                "default", "checked"}
    assert set(planner["default_positions"]) == {"j1"}
    # The arm's matrix checks no pair: no estimate (the summary prints none).
    assert {p[3] for p in matrix["pairs"]} == {True}
    assert baked.self_collision_estimate is None
    assert "self-collision estimate" not in run.stdout
    # Without the matrix: adjacent pairs only, the zero pose unchecked.
    plain = medspheres.bake_robot(arm, spheres_per_link=6, self_collision=False)
    assert plain.planner["default_from"] == "zero_unchecked"
    assert plain.planner["self_collision"]["samples"] == 0
    assert plain.self_collision_estimate is None


FOLDING_URDF = """<?xml version="1.0"?>
<robot name="fold">
  <link name="base"><collision><geometry><box size="0.3 0.3 0.05"/></geometry></collision></link>
  <link name="upper">
    <collision><origin xyz="0 0 0.1"/><geometry><box size="0.04 0.04 0.2"/></geometry></collision>
  </link>
  <link name="fore">
    <collision><origin xyz="0 0 0.1"/><geometry><box size="0.04 0.04 0.2"/></geometry></collision>
  </link>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="upper"/><origin xyz="0 0 0.03"/>
    <axis xyz="0 1 0"/><limit lower="-1.5" upper="1.5" velocity="1" effort="1"/>
  </joint>
  <joint name="j2" type="revolute">
    <parent link="upper"/><child link="fore"/><origin xyz="0 0 0.2"/>
    <axis xyz="0 1 0"/><limit lower="-3" upper="3" velocity="1" effort="1"/>
  </joint>
</robot>
"""


def test_bake_robot_self_collision_estimate_equals_cli(cli, tmp_path):
    """RobotBake.self_collision_estimate: the robot command's summary line, in numbers, on an
    arm whose forearm folds onto its base; none when asked for none."""
    urdf = tmp_path / "fold.urdf"
    urdf.write_text(FOLDING_URDF)
    options = dict(spheres_per_link=6, self_collision_samples=300)
    baked = medspheres.bake_robot(urdf, **options, self_collision_estimate=500)
    assert ["base", "fore", "checked", False] in baked.planner["self_collision"]["pairs"]
    run = cli("robot", urdf, "-o", tmp_path / "cli", "--spheres-per-link", "6",
              "--self-collision-samples", "300", "--self-collision-estimate", "500")
    estimate = baked.self_collision_estimate
    assert estimate["samples"] == 500 and estimate["seed"] == 1 + 7919
    assert estimate["false_negatives"] == 0  # covering sets
    line = (f"self-collision estimate: of 500 other random configurations (seed 7920), "
            f"{estimate['false_positives']} (")
    assert line in run.stdout, run.stdout
    assert ", and 0 have a checked pair's meshes touching" in run.stdout, run.stdout
    for link1, link2, n in estimate["alone"][:3]:
        assert f"{link1}-{link2} {n}" in run.stdout, run.stdout
    assert sum(n for _, _, n in estimate["alone"]) <= estimate["false_positives"]
    none = medspheres.bake_robot(urdf, **options, self_collision_estimate=0)
    assert none.self_collision_estimate is None


def test_bake_robot_srdf_pairs_and_end_effectors(cli, arm, tmp_path):
    """srdf=: its disabled pairs skipped as given (their reasons kept), its end effectors the
    tool frames; the same files as the robot command's --srdf; a pair naming no link refused."""
    srdf = tmp_path / "arm_given.srdf"
    srdf.write_text('<robot name="arm">\n'
                    '  <end_effector name="tool" parent_link="upper" group="g"/>\n'
                    '  <disable_collisions link1="base" link2="hand" reason="User"/>\n'
                    '</robot>\n')
    ours_dir, theirs_dir = tmp_path / "py", tmp_path / "cli"
    baked = medspheres.bake_robot(arm, ours_dir, spheres_per_link=6, srdf=srdf,
                                  self_collision_samples=200)
    cli("robot", arm, "-o", theirs_dir, "--spheres-per-link", "6", "-q", "--srdf", srdf,
        "--self-collision-samples", "200")
    for name in ["arm.curobo.yml", "arm.xrdf", "arm.srdf", "arm.self_collision.txt"]:
        assert (ours_dir / name).read_bytes() == (theirs_dir / name).read_bytes(), name
    planner = baked.planner
    assert planner["tool_frames"] == ["upper"] and planner["tool_frames_from"] == "srdf"
    given = [p for p in planner["self_collision"]["pairs"] if p[2] == "given"]
    assert [sorted(p[:2]) for p in given] == [["base", "hand"]]
    assert given[0][3] is True and given[0][4] == "User"
    written = (ours_dir / "arm.srdf").read_text()
    assert 'reason="User"' in written and "base" in written

    bad = tmp_path / "bad.srdf"
    bad.write_text('<robot name="arm"><disable_collisions link1="base" link2="nope"/></robot>')
    with pytest.raises(medspheres.InputError, match="nope"):
        medspheres.bake_robot(arm, spheres_per_link=6, srdf=bad)


def _thin_cup_stl(path, radius=0.5, height=2.0, wall=0.03, slices=48):
    """A closed cup whose material is a thin wall: its profile revolved about z."""
    profile = [(0.0, 0.0), (radius, 0.0), (radius, height), (radius - wall, height),
               (radius - wall, wall), (0.0, wall)]
    angles = np.linspace(0.0, 2.0 * np.pi, slices, endpoint=False)

    def point(r, z, k):
        a = angles[k % slices]
        return (r * np.cos(a), r * np.sin(a), z)

    facets = []
    for (r0, z0), (r1, z1) in zip(profile, profile[1:]):
        for k in range(slices):
            quad = [point(r0, z0, k), point(r1, z1, k), point(r1, z1, k + 1), point(r0, z0, k + 1)]
            for tri in (quad[:3], [quad[0], quad[2], quad[3]]):
                if len(set(tri)) == 3:  # the axis collapses half of a quad
                    facets.append(tri)
    with open(path, "w") as f:
        f.write("solid cup\n")
        for tri in facets:
            f.write("facet normal 0 0 0\nouter loop\n")
            for v in tri:
                f.write("vertex %.17g %.17g %.17g\n" % v)
            f.write("endloop\nendfacet\n")
        f.write("endsolid cup\n")


def test_bake_robot_fill_equals_cli(cli, tmp_path):
    """fill=True: a thin-shelled link's inner set on its filled solid, as --fill bakes it, the
    robot file marking the link; the real solid's inner set barely fills it."""
    _thin_cup_stl(tmp_path / "cup.stl")
    urdf = tmp_path / "cup.urdf"
    urdf.write_text('<robot name="cup"><link name="cup"><collision><geometry>'
                    '<mesh filename="cup.stl"/></geometry></collision></link></robot>\n')
    filled = medspheres.bake_robot(urdf, tmp_path / "py", fill=True, formats=["robot"],
                                   self_collision=False)
    cli("robot", urdf, "-o", tmp_path / "cli", "--fill", "--format", "robot",
        "--no-self-collision", "-q")
    for which in ("inner", "outer"):
        ours = medspheres.load(tmp_path / "py" / "cup.robot.json", set=which).links["cup"]
        theirs = medspheres.load(tmp_path / "cli" / "cup.robot.json", set=which).links["cup"]
        assert ours.tobytes() == theirs.tobytes(), which
    plain = medspheres.bake_robot(urdf, self_collision=False)
    ours, theirs = filled.stats[0], plain.stats[0]
    assert ours["inner_filled"] and not theirs["inner_filled"]
    assert ours["nerr"] <= 0.3 < 0.5 < theirs["nerr"]
    for side in ("py", "cli"):
        assert '"inner_solid": "filled"' in (tmp_path / side / "cup.robot.json").read_text()


def test_bake_robot_fill_covers_equals_cli(cli, tmp_path):
    """fill_covers=True: a thin-shelled link's covering set baked on its filled solid, as
    --fill-covers bakes it, certified and marked in the robot file; the inner set unchanged."""
    _thin_cup_stl(tmp_path / "cup.stl")
    urdf = tmp_path / "cup.urdf"
    urdf.write_text('<robot name="cup"><link name="cup"><collision><geometry>'
                    '<mesh filename="cup.stl"/></geometry></collision></link></robot>\n')
    filled = medspheres.bake_robot(urdf, tmp_path / "py", fill_covers=True, formats=["robot"],
                                   self_collision=False, measure=False, spheres_per_link=8)
    cli("robot", urdf, "-o", tmp_path / "cli", "--fill-covers", "--format", "robot",
        "--no-self-collision", "--no-measure", "--spheres-per-link", "8", "-q")
    for which in ("inner", "outer"):
        ours = medspheres.load(tmp_path / "py" / "cup.robot.json", set=which).links["cup"]
        theirs = medspheres.load(tmp_path / "cli" / "cup.robot.json", set=which).links["cup"]
        assert ours.tobytes() == theirs.tobytes(), which
    plain = medspheres.bake_robot(urdf, self_collision=False, measure=False, spheres_per_link=8)
    assert filled.stats[0]["outer_filled"] and not plain.stats[0]["outer_filled"]
    assert filled.stats[0]["outer_certified"]
    assert filled.links["cup"]["inner"].tobytes() == plain.links["cup"]["inner"].tobytes()
    assert filled.links["cup"]["outer"].tobytes() != plain.links["cup"]["outer"].tobytes()
    for side in ("py", "cli"):
        assert '"cover_solid": "filled"' in (tmp_path / side / "cup.robot.json").read_text()


def test_bake_robot_warns_of_what_curobos_urdf_parser_refuses(tmp_path):
    """A continuous joint without <limit> is legal URDF, but cuRobo's parser needs its effort
    and velocity: bake_robot says so by name, as the robot command does; with the limit, not."""
    text = ('<robot name="spin"><link name="a"><collision><geometry><box size="0.1 0.1 0.1"/>'
            '</geometry></collision></link><link name="b"><collision><geometry>'
            '<sphere radius="0.05"/></geometry></collision></link>'
            '<joint name="wheel" type="continuous"><parent link="a"/><child link="b"/>'
            '<origin xyz="0 0 0.3"/><axis xyz="0 1 0"/>LIMIT</joint></robot>\n')
    bare, limited = tmp_path / "bare.urdf", tmp_path / "limited.urdf"
    bare.write_text(text.replace("LIMIT", ""))
    limited.write_text(text.replace("LIMIT", '<limit effort="1" velocity="1"/>'))
    with pytest.warns(UserWarning, match="continuous joint 'wheel' has no <limit>"):
        medspheres.bake_robot(bare, spheres_per_link=2, self_collision=False)
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        medspheres.bake_robot(limited, spheres_per_link=2, self_collision=False)


def test_bake_robot_warns_of_a_robot_without_collision_geometry(tmp_path):
    """A robot with visual geometry alone bakes no sphere: bake_robot says so, as the robot
    command does, and names from_visual, which bakes it."""
    urdf = tmp_path / "bare.urdf"
    urdf.write_text('<robot name="bare"><link name="v"><visual><geometry>'
                    '<box size="0.1 0.2 0.3"/></geometry></visual></link></robot>\n')
    with pytest.warns(UserWarning, match="no link has collision geometry.*from_visual=True"):
        bare = medspheres.bake_robot(urdf, spheres_per_link=2, self_collision=False)
    assert len(bare.links["v"]["outer"]) == 0
    import warnings
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        visual = medspheres.bake_robot(urdf, spheres_per_link=2, self_collision=False,
                                       from_visual=True)
    assert len(visual.links["v"]["outer"]) > 0
    # The one warning left: a robot without an actuated joint gets no XRDF.
    assert len(caught) == 1 and "no actuated joint" in str(caught[0].message)
