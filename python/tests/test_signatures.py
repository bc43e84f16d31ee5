"""The type stubs (`_octsolid.pyi`) match what the module takes: every function's and
method's parameters (names, order, keyword-only or not, and defaults where the module
states them) in the stub are the run-time signature's (`__text_signature__`, which PyO3
writes from the Rust `#[pyo3(signature = ...)]`)."""

import ast
import inspect
import pathlib

import octsolid as o

STUB = pathlib.Path(o.__file__).parent / "_octsolid.pyi"
NO_DEFAULT = object()


def value(expression):
    """A stub default's value: a constant, or arithmetic of constants (`2**27`)."""
    return eval(compile(ast.Expression(expression), str(STUB), "eval"), {"__builtins__": {}})


def stub_params(node):
    """`[(name, kind, default)]` of a stub's `def`, `self` left out."""
    a = node.args
    params = []
    positional = a.posonlyargs + a.args
    defaults = [NO_DEFAULT] * (len(positional) - len(a.defaults)) + [value(d) for d in a.defaults]
    for arg, default in zip(positional, defaults):
        params.append((arg.arg, "positional", default))
    for arg, default in zip(a.kwonlyargs, a.kw_defaults):
        params.append((arg.arg, "keyword", NO_DEFAULT if default is None else value(default)))
    return [p for p in params if p[0] != "self"]


def runtime_params(f):
    """The same list from the run-time signature; `None` for a default PyO3 shows as `...`."""
    params = []
    for p in inspect.signature(f).parameters.values():
        if p.name == "self":
            continue
        kind = "keyword" if p.kind is p.KEYWORD_ONLY else "positional"
        default = NO_DEFAULT if p.default is p.empty else (None if p.default is ... else p.default)
        params.append((p.name, kind, default, p.default is ...))
    return params


def stubbed_callables():
    """`(qualified name, run-time object, stub def)`, each name's first stub (overloads:
    the first is the general one)."""
    seen = set()
    tree = ast.parse(STUB.read_text())
    for node in tree.body:
        defs = []
        if isinstance(node, ast.FunctionDef):
            defs.append((node.name, getattr(o, node.name), node))
        elif isinstance(node, ast.ClassDef) and hasattr(o, node.name):
            cls = getattr(o, node.name)
            for item in node.body:
                if not isinstance(item, ast.FunctionDef) or item.decorator_list:
                    continue  # a docstring, a field, a property
                if item.name.startswith("__") and item.name != "__init__":
                    # Operators are Python's slots (`__or__(self, value, /)`): their stubs
                    # name the operand for readers only.
                    continue
                target = cls if item.name == "__init__" else getattr(cls, item.name)
                defs.append((f"{node.name}.{item.name}", target, item))
        for name, target, item in defs:
            if name not in seen:
                seen.add(name)
                yield name, target, item


def test_the_stubs_take_the_parameters_the_module_takes():
    checked = 0
    for name, target, node in stubbed_callables():
        try:
            runtime = runtime_params(target)
        except (ValueError, TypeError) as e:
            raise AssertionError(f"{name}: no signature at run time ({e})") from None
        stub = stub_params(node)
        assert [p[:2] for p in stub] == [p[:2] for p in runtime], f"{name}: stub {stub} != module {runtime}"
        for (pname, _, sdefault), (_, _, rdefault, unknown) in zip(stub, runtime):
            if unknown:  # a Rust constant: the stub states it, the module shows `...`
                assert sdefault is not NO_DEFAULT, f"{name}({pname}): the module has a default, the stub none"
                continue
            assert sdefault == rdefault, f"{name}({pname}): stub default {sdefault!r}, module {rdefault!r}"
        checked += 1
    assert checked >= 40, checked
