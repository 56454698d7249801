"""Every public name of the package, and every public method and property of its classes, has a docstring
(help(ogf.Map) is the reference a user reads first)."""

import inspect

import ogf


# Map and NavGrid are made by load_map() and project(), not constructed: their __init__ only refuses.
CONSTRUCTED = ("MapClient", "NavClient")


def public_members(cls):
    for name, member in inspect.getmembers(cls):
        if name.startswith("_") and not (name == "__init__" and cls.__name__ in CONSTRUCTED):
            continue
        yield name, member


def test_every_public_name_method_and_property_has_a_docstring():
    missing = []
    assert ogf.__doc__ and ogf._ogf.__doc__
    for name in ogf.__all__:
        obj = getattr(ogf, name)
        if isinstance(obj, int):
            continue
        if not (obj.__doc__ or "").strip():
            missing.append(name)
        if inspect.isclass(obj) and obj is not ogf.MapFileError:
            for member_name, member in public_members(obj):
                doc = member.__doc__ or ""
                # pybind11 puts the signature first; a docstring is text beyond it.
                text = "\n".join(line for line in doc.splitlines() if "(self" not in line and line.strip())
                if not text.strip():
                    missing.append(f"{name}.{member_name}")
    assert missing == []
