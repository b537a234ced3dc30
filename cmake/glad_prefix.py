"""Renames the glad2 loader's symbols for Sluice: every glad_*, gladLoad* and GLAD_GL_* /
GLAD_EGL_* identifier gets the prefix sluice_, and glad/ becomes sluice_glad/, so a program that
links its own glad (or any loader) beside Sluice shares no symbol and no header with it.

usage: python3 glad_prefix.py GENERATED_DIR OUT_DIR
"""
import pathlib
import re
import shutil
import sys

IDENTIFIER = re.compile(r"\b(glad_|gladLoad|GLAD_GL_|GLAD_EGL_)")
INCLUDE = re.compile(r"#include <glad/")


def rewrite(text: str) -> str:
    return INCLUDE.sub("#include <sluice_glad/", IDENTIFIER.sub(r"sluice_\1", text))


def main() -> int:
    source, out = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
    if out.exists():
        shutil.rmtree(out)
    for path in source.rglob("*"):
        if not path.is_file():
            continue
        relative = path.relative_to(source)
        parts = ["sluice_glad" if p == "glad" else p for p in relative.parts]
        target = out.joinpath(*parts)
        target.parent.mkdir(parents=True, exist_ok=True)
        if relative.parts[0] == "include" and relative.parts[1] != "glad":
            shutil.copyfile(path, target)  # KHR/ and EGL/ platform headers: Khronos' own
        else:
            target.write_text(rewrite(path.read_text()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
