"""The package's surface: every name the extension defines is exported, stubbed and documented."""

import ast
import pathlib
import re

import medspheres
from medspheres import _medspheres

STUB = pathlib.Path(__file__).resolve().parent.parent / "medspheres" / "__init__.pyi"


def public_names():
    return sorted(n for n in dir(_medspheres) if not n.startswith("_"))


def test_every_name_is_exported_stubbed_and_documented():
    tree = ast.parse(STUB.read_text())
    stubbed = {node.name for node in tree.body if isinstance(node, (ast.FunctionDef, ast.ClassDef))}
    assert public_names() == sorted(medspheres.__all__)
    for name in public_names():
        assert name in stubbed, name
        assert getattr(medspheres, name).__doc__, name


def signature_parameters(function):
    """The parameter names of each signature pybind11 writes atop the function's docstring."""
    out = []
    for line in (function.__doc__ or "").splitlines():
        if not re.match(r"^(\d+\. )?%s\(" % function.__name__, line):
            continue
        depth, current, names = 0, "", set()
        for ch in line[line.index("(") + 1:line.rindex(")")] + ",":
            depth += ch in "([{"
            depth -= ch in ")]}"
            if ch == "," and depth == 0:
                name = current.split(":")[0].split("=")[0].strip()
                if name and name != "*":
                    names.add(name)
                current = ""
            else:
                current += ch
        out.append(names)
    return out


def test_stubbed_functions_take_the_modules_parameters():
    """Each stubbed function (not overloaded) names the parameters the module's takes."""
    checked = 0
    for node in ast.parse(STUB.read_text()).body:
        if not isinstance(node, ast.FunctionDef) or node.name not in public_names():
            continue
        if any(getattr(d, "id", None) == "overload" for d in node.decorator_list):
            continue
        a = node.args
        stubbed = {x.arg for x in a.posonlyargs + a.args + a.kwonlyargs}
        signatures = signature_parameters(getattr(medspheres, node.name))
        assert signatures, node.name
        assert stubbed in signatures, (node.name, stubbed ^ signatures[0])
        checked += 1
    assert checked >= 10


def test_stubbed_methods_exist():
    tree = ast.parse(STUB.read_text())
    for node in tree.body:
        if isinstance(node, ast.ClassDef) and node.name in public_names():
            cls = getattr(medspheres, node.name)
            for item in node.body:
                if isinstance(item, ast.FunctionDef):
                    assert hasattr(cls, item.name), (node.name, item.name)
