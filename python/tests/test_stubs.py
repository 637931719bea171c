"""The type stubs (.pyi) name exactly what the compiled module exposes."""
import ast
import pathlib

import plucker
from plucker import _plucker, factors

PACKAGE = pathlib.Path(plucker.__file__).parent


def stub_names(stub):
    tree = ast.parse((PACKAGE / stub).read_text())
    return {n.name for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}


def public(module):
    return {n for n in dir(module) if not n.startswith("_") and callable(getattr(module, n))}


def test_stubs_match_the_module():
    assert stub_names("_plucker.pyi") == public(_plucker) - {"factors"}
    assert stub_names("factors.pyi") == public(factors)


def test_everything_has_a_docstring():
    for module in (_plucker, factors):
        for name in public(module):
            assert (getattr(module, name).__doc__ or "").strip(), name
