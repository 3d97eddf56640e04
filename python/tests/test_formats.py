"""load / save / convert in every format `medspheres convert` knows: the CLI's bytes."""

import numpy as np
import pytest

import medspheres

ONE_SET = {"spheres": "s.json", "foam": "s.foam.json", "sph": "s.sph"}
PER_LINK = {"curobo": "s.yml", "xrdf": "s.xrdf", "srdf": "s.srdf", "foam": "s.foam.json"}


@pytest.fixture(scope="module")
def baked(tmp_path_factory, eight):
    s = medspheres.bake(eight, resolution=12)
    path = tmp_path_factory.mktemp("baked") / "eight.spheres.json"
    s.save(path)
    return s, path


@pytest.mark.parametrize("fmt, name", sorted(ONE_SET.items()))
def test_one_set_formats_match_convert(cli, baked, tmp_path, fmt, name):
    s, src = baked
    ours, theirs = tmp_path / ("py-" + name), tmp_path / ("cli-" + name)
    s.save(ours)
    cli("convert", src, theirs)
    assert ours.read_bytes() == theirs.read_bytes()
    back = medspheres.load(ours)
    assert back.set is not None and np.array_equal(back.set.spheres, s.spheres)


@pytest.mark.parametrize("fmt, name", sorted(PER_LINK.items()))
def test_per_link_formats_match_convert(cli, baked, tmp_path, fmt, name):
    s, src = baked
    ours, theirs = tmp_path / ("py-" + name), tmp_path / ("cli-" + name)
    medspheres.convert(src, ours, to_format=fmt, link="body")
    cli("convert", src, theirs, "--to", fmt, "--link", "body")
    assert ours.read_bytes() == theirs.read_bytes()
    if fmt != "foam":
        doc = medspheres.load(ours)
        assert list(doc.links) == ["body"]
        links = doc.links["body"]
        assert links.shape == (len(s), 4) and links.dtype == np.float64
        assert np.array_equal(links, s.spheres)


def test_bad_formats_raise(baked, tmp_path):
    s, src = baked
    with pytest.raises(medspheres.InputError) as info:
        s.save(tmp_path / "x.json", format="nope")
    assert "unknown format" in str(info.value)
    with pytest.raises(medspheres.InputError):
        s.save(tmp_path / "x.unknown")
    with pytest.raises(medspheres.InputError) as info:
        medspheres.load(tmp_path / "missing.json")
    assert info.value.kind == "file_missing"
    with pytest.raises(ValueError):
        medspheres.load(src, set="middle")
