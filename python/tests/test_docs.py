"""Every public name has a docstring at run time and an entry in the type stubs."""

import ast
import pathlib

import octsolid as o

PACKAGE = pathlib.Path(o.__file__).parent


def stub_names():
    names = set()
    for path in (PACKAGE / "_octsolid.pyi", PACKAGE / "errors.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, (ast.ClassDef, ast.FunctionDef)):
                names.add(node.name)
    return names


def test_every_name_is_documented_and_stubbed():
    stubbed = stub_names()
    assert (PACKAGE / "py.typed").exists()
    for name in o.__all__:
        assert name in stubbed, name
        assert (getattr(o, name).__doc__ or "").strip(), name
    for cls in (o.Solid, o.Shape):
        for name in dir(cls):
            if not name.startswith("__"):
                assert name in stubbed, f"{cls.__name__}.{name}"
                assert (getattr(cls, name).__doc__ or "").strip(), f"{cls.__name__}.{name}"
