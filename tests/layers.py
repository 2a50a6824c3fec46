"""The layers of the source tree (docs/ARCHITECTURE.md): each folder is one
layer, and a file includes headers of its own folder and of layers below
its own, never above nor beside. Reads every #include "..." line of the
project's C and C++ sources and fails, naming FILE:LINE, on an include that
runs up or sideways, or that names no header of the project it can find.

    layers.py SOURCE_ROOT
"""

import os
import re
import sys

from source_tree import project_files

# Lowest first. A folder not listed belongs to the nearest listed folder
# above it. tests/, bench/ and examples/ stand on everything.
LAYERS = [
    ["libtcs_preload/include", "simhost/include"],  # what both sides of a line share
    ["common", "libtcs_preload"],
    ["simhost", "scenario", "trace", "wires"],
    ["coordinator"],
    ["cli", "coordinatord/dds"],
    ["tools", "coordinatord"],
]
TOP = ["tests", "bench", "examples"]
SOURCES = (".c", ".cc", ".h", ".cpp", ".idl")  # (an .idl's header is generated)


def folder_of(path):
    """The listed folder a file belongs to, or None for one outside them."""
    best = None
    for names in LAYERS + [TOP]:
        for name in names:
            if (path == name or path.startswith(name + "/")) and (best is None or len(name) > len(best)):
                best = name
    return best


def layer_of(folder):
    for i, names in enumerate(LAYERS):
        if folder in names:
            return i
    return len(LAYERS)  # the top


def main(root):
    files = list(project_files(root, SOURCES))
    # Where a header named by an include can be: its path from any folder
    # the build puts on the include path (every folder with headers).
    by_name = {}
    for f in files:
        parts = f.split("/")
        for i in range(len(parts)):
            by_name.setdefault("/".join(parts[i:]), []).append(f)
        if f.endswith(".idl"):
            by_name.setdefault(os.path.basename(f)[:-4] + ".h", []).append(f)
    errors = []
    for f in files:
        here = folder_of(f)
        if here is None or f.endswith(".idl"):
            continue
        with open(os.path.join(root, f), errors="replace") as text:
            for n, line in enumerate(text, 1):
                m = re.match(r'\s*#\s*include\s+"([^"]+)"', line)
                if not m:
                    continue
                name = m.group(1)
                local = os.path.normpath(os.path.join(os.path.dirname(f), name))
                found = [local] if local in files else by_name.get(name, [])
                if not found:
                    errors.append("%s:%d: includes \"%s\", which is no header of the project" % (f, n, name))
                    continue
                # Of several headers by that name, the build finds the one
                # in the including file's folder first.
                target = next((h for h in found if folder_of(h) == here), found[0])
                there = folder_of(target)
                if there == here or there is None:
                    continue
                if layer_of(there) >= layer_of(here):
                    errors.append("%s:%d: includes %s from %s, a layer %s its own (%s)" %
                                  (f, n, target, there, "beside" if layer_of(there) == layer_of(here) else "above",
                                   here))
    for e in errors:
        print(e)
    print("%d files, %d includes that run up or sideways" % (len(files), len(errors)))
    return 1 if errors else 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print("usage: layers.py SOURCE_ROOT", file=sys.stderr)
        sys.exit(2)
    sys.exit(main(sys.argv[1]))
