"""The type stubs (frnn/__init__.pyi) describe exactly what the module has."""
import ast
import inspect
import os

import frnn


def stub_tree():
    path = os.path.join(os.path.dirname(frnn.__file__), "__init__.pyi")
    with open(path) as f:
        return ast.parse(f.read())


def public(names):
    return {n for n in names if not n.startswith("_") or n in ("__init__", "__len__")}


def test_stub_names_match_the_module():
    tree = stub_tree()
    top = {n.name for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    assert top == set(frnn.__all__) - {"__version__"}
    grid = next(n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == "Grid")
    stubbed = public(n.name for n in grid.body if isinstance(n, ast.FunctionDef))
    assert stubbed == public(dir(frnn.Grid))


def test_stub_parameters_match_the_docstring_signatures():
    """pybind11 writes each signature first in __doc__: the stub's parameter names agree."""
    grid = next(n for n in stub_tree().body if isinstance(n, ast.ClassDef) and n.name == "Grid")
    for node in grid.body:
        if not isinstance(node, ast.FunctionDef) or node.name.startswith("_"):
            continue
        member = inspect.getattr_static(frnn.Grid, node.name)
        if isinstance(member, property):
            continue
        names = [a.arg for a in node.args.args + node.args.kwonlyargs]
        doc_signature = getattr(frnn.Grid, node.name).__doc__.splitlines()[0]
        for name in names[1:]:
            assert f"{name}:" in doc_signature, (node.name, name, doc_signature)
