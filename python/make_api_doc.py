#!/usr/bin/env python3
"""Writes the API reference of docs/python.md from the module's docstrings (their only source).

  PYTHONPATH=build/release/python /usr/bin/python3 python/make_api_doc.py [--check]

Replaces everything after the marker line of docs/python.md; --check exits 1 when the file is
not what it would write (python/tests/test_docs.py runs that check).
"""
import inspect
import pathlib
import sys

import stickslip

MARKER = "<!-- API reference: generated from the docstrings by python/make_api_doc.py -->"
DOC = pathlib.Path(__file__).resolve().parents[1] / "docs" / "python.md"


def entry(name, obj):
    doc = inspect.getdoc(obj) or ""
    return f"### `{name}`\n\n```text\n{doc}\n```\n"


def reference():
    parts = [MARKER, "", "## API reference", "", "### Module `stickslip`", "", "```text",
             inspect.getdoc(stickslip), "```", ""]
    for name in ("read_case", "contact_laws"):
        parts.append(entry(f"stickslip.{name}", getattr(stickslip, name)))
    parts.append(entry("stickslip.InvalidInput", stickslip.InvalidInput))
    parts.append(entry("stickslip.StickslipWarning", stickslip.StickslipWarning))
    for cls in (stickslip.Case, stickslip.Solution):
        parts.append(entry(f"stickslip.{cls.__name__}", cls))
        for member, value in cls.__dict__.items():
            if member.startswith("_") and member != "__init__":
                continue
            doc = inspect.getdoc(value)
            if not doc or member == "__init__" and "Overloaded" in doc:
                continue
            if isinstance(value, property):
                parts.append(f"#### `{cls.__name__}.{member}` (property)\n\n```text\n{doc}\n```\n")
            elif member == "__init__":
                parts.append(f"#### `{cls.__name__}(...)`\n\n```text\n{doc}\n```\n")
            else:
                parts.append(f"#### `{cls.__name__}.{member}`\n\n```text\n{doc}\n```\n")
    return "\n".join(parts).rstrip() + "\n"


def main():
    text = DOC.read_text()
    if MARKER not in text:
        sys.exit(f"{DOC}: no marker line {MARKER}")
    new = text[: text.index(MARKER)] + reference()
    if "--check" in sys.argv:
        if new != text:
            sys.exit(f"{DOC} is not current: run {sys.argv[0]}")
        return
    DOC.write_text(new)


if __name__ == "__main__":
    main()
