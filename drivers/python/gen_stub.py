#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""gen_stub.py EXTENSION SIGNATURE_PY TEMPLATE OUTPUT -- the type stub
taper/__init__.pyi, written when the package is built (drivers/python/
meson.build): TEMPLATE (package/__init__.pyi.in) with the keyword-only
parameters of simulate(), theory() and chain(), one per scene variable
that the call takes, with its type and default.  The table is read from
the extension just built (EXTENSION: taper._core, loaded from its file),
and the rows, types and the variables left out are the package's own
(SIGNATURE_PY: package/_signature.py), so the stub says what the package
does at run time."""

import importlib.util
import sys


def load(name, path):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def parameters(signature, rows, func):
    lines = []
    for row in signature.keyword_rows(rows, func):
        lines.append(f"    {row['name']}: {signature.annotation_text(row)} = {row['default']!r},")
    return "\n".join(lines)


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    extension, signature_py, template, output = sys.argv[1:]
    core = load("taper._core", extension)
    signature = load("taper._signature", signature_py)
    rows = core.variables()
    text = open(template, encoding="utf-8").read()
    for func in ("simulate", "theory", "chain"):
        text = text.replace(f"@{func.upper()}@", parameters(signature, rows, func))
    with open(output, "w", encoding="utf-8") as f:
        f.write(text)


if __name__ == "__main__":
    main()
