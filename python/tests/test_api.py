"""The package's surface: every name the extension defines is exported, stubbed and documented."""

import ast
import pathlib

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


def test_stubbed_methods_exist():
    tree = ast.parse(STUB.read_text())
    for node in tree.body:
        if isinstance(node, ast.ClassDef) and node.name in public_names():
            cls = getattr(medspheres, node.name)
            for item in node.body:
                if isinstance(item, ast.FunctionDef):
                    assert hasattr(cls, item.name), (node.name, item.name)
