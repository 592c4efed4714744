"""Shared helpers of the reference scripts in this folder.

Each script computes the reference of one model of models/siconos/ independently of zenosim's
code (closed forms, or its own event-driven computation in mpmath) and writes
models/siconos/references/<name>.json. This module only reads the model file's parameters (to
check them against the values the script takes from the Siconos example) and writes the JSON.

Needs Python 3.11 (tomllib) and mpmath.
"""

import math
import pathlib
import tomllib

import mpmath

ROOT = pathlib.Path(__file__).resolve().parents[3]
COMMIT = "b6c9bfd1940a69dae512a3e39cf5f1a951e3eebe"


def model_path(name):
    return ROOT / "models" / "siconos" / f"{name}.toml"


def read_model(name):
    with open(model_path(name), "rb") as f:
        return tomllib.load(f)


def _evaluate(formula, names):
    """Evaluates a parameter formula of a model file (numbers, names, + - * / ^, pi, sqrt...)."""
    if not isinstance(formula, str):
        return mpmath.mpf(formula)
    space = {"pi": mpmath.pi, "sqrt": mpmath.sqrt, "sin": mpmath.sin, "cos": mpmath.cos}
    space.update(names)
    return eval(formula.replace("^", "**"), {"__builtins__": {}}, space)


def parameters(name):
    """The model file's parameters, evaluated in mpmath in the file's order."""
    values = {}
    for key, formula in read_model(name)["parameters"].items():
        values[key] = mpmath.mpf(_evaluate(formula, values))
    return values


def check_parameters(name, expected, rel=mpmath.mpf("1e-15")):
    """Stops unless the model file's parameters equal the example's values (to rounding)."""
    values = parameters(name)
    for key, value in expected.items():
        got = values[key]
        if abs(got - value) > rel * max(abs(value), 1):
            raise SystemExit(f"{name}.toml: parameter {key} = {got}, the example has {value}")
    return values


def _number(x):
    x = float(x)
    if not math.isfinite(x):
        raise ValueError(f"not a finite number: {x}")
    return format(x, ".17g")


def _dump(value, indent):
    pad = "  " * indent
    if isinstance(value, dict):
        if not value:
            return "{}"
        items = [f'{pad}  "{k}": {_dump(v, indent + 1)}' for k, v in value.items()]
        return "{\n" + ",\n".join(items) + "\n" + pad + "}"
    if isinstance(value, (list, tuple)):
        if not value:
            return "[]"
        if all(not isinstance(v, (dict, list, tuple)) for v in value):
            return "[" + ", ".join(_dump(v, indent + 1) for v in value) + "]"
        items = [f"{pad}  {_dump(v, indent + 1)}" for v in value]
        return "[\n" + ",\n".join(items) + "\n" + pad + "]"
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    return _number(value)


def write_reference(name, example, method, accuracy, **fields):
    """Writes models/siconos/references/<name>.json; numbers with 17 significant digits."""
    document = {
        "example": example,
        "commit": COMMIT,
        "model": f"models/siconos/{name}.toml",
        "method": method,
        "accuracy": accuracy,
    }
    document.update(fields)
    path = ROOT / "models" / "siconos" / "references" / f"{name}.json"
    path.write_text(_dump(document, 0) + "\n")
    print(f"wrote {path.relative_to(ROOT)}")
