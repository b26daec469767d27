"""numpydoc's validator over the public API: parameters documented, none unknown, Returns given.

The public API is every function and class named in the ``__all__`` of a public module of
:mod:`rankedassign` and :mod:`oracle` (a module whose dotted name has no part starting with an
underscore), with the public methods of those classes. Each must pass numpydoc's checks

* ``PR01`` — every parameter documented;
* ``PR02`` — no documented parameter that the signature lacks;
* ``RT01`` — a Returns section (functions and methods that return something).

A result record (a named tuple or a dataclass) documents its fields under Attributes instead of
Parameters: for those, every field must be listed in Attributes and nothing else there may be
unknown.
"""

from __future__ import annotations

import dataclasses
import importlib
import inspect
import pkgutil

import pytest

numpydoc_validate = pytest.importorskip("numpydoc.validate")
from numpydoc.docscrape import ClassDoc  # noqa: E402

import oracle  # noqa: E402
import rankedassign  # noqa: E402

CODES = ("PR01", "PR02", "RT01")


def _public_modules():
    for package in (rankedassign, oracle):
        yield package.__name__
        for info in pkgutil.walk_packages(package.__path__, package.__name__ + "."):
            if not any(part.startswith("_") for part in info.name.split(".")):
                yield info.name


def _is_record(cls) -> bool:
    return dataclasses.is_dataclass(cls) or (issubclass(cls, tuple) and hasattr(cls, "_fields"))


def _fields(cls) -> list[str]:
    if dataclasses.is_dataclass(cls):
        return [f.name for f in dataclasses.fields(cls) if f.init or f.repr]
    return list(cls._fields)


def _api():
    """``{qualified name: object}`` of the public API (functions, classes, public methods)."""
    out = {}
    for name in _public_modules():
        module = importlib.import_module(name)
        for attr in getattr(module, "__all__", ()):
            obj = getattr(module, attr, None)
            if not (inspect.isfunction(obj) or inspect.isclass(obj)):
                continue
            if obj.__module__.split(".")[0] not in ("rankedassign", "oracle"):
                continue
            qual = f"{obj.__module__}.{obj.__qualname__}"
            out[qual] = obj
            if inspect.isclass(obj):
                for meth, value in vars(obj).items():
                    if meth.startswith("_"):
                        continue
                    if isinstance(value, (classmethod, staticmethod)):
                        value = value.__func__
                    if inspect.isfunction(value):
                        out[f"{qual}.{meth}"] = value
    return out


API = _api()


def test_the_api_is_found():
    assert "rankedassign.samplers.sample_short_chains" in API
    assert "oracle.exact.marginals" in API
    assert "rankedassign.tracking.single.lmb.LMBFilter.step" in API
    assert len(API) > 150


@pytest.mark.parametrize("name", sorted(API))
def test_numpydoc(name):
    obj = API[name]
    if inspect.isclass(obj) and _is_record(obj):
        doc = ClassDoc(obj)
        listed = [n for item in doc["Attributes"] for n in item.name.split(", ")]
        missing = [f for f in _fields(obj) if f not in listed]
        assert not missing, f"{name}: fields {missing} not in its Attributes section"
        unknown = [n for n in listed if n not in _fields(obj) and not hasattr(obj, n)]
        assert not unknown, f"{name}: Attributes {unknown} are no fields or attributes"
        return
    result = numpydoc_validate.validate(name)
    errors = [f"{code} {msg}" for code, msg in result["errors"] if code in CODES]
    assert not errors, f"{name}: " + "; ".join(errors)
