"""The project's own source files, as the layout checks read them
(layers.py, source_rules.py): every file below the source root with one of
the given endings, but for build folders, .git, node_modules and
subprojects."""

import os

SKIP = {".git", "node_modules", "subprojects"}


def project_files(root, endings):
    """The paths, relative to root and sorted, of the files ending in one
    of `endings` (a tuple)."""
    for base, dirs, files in os.walk(root):
        dirs[:] = sorted(d for d in dirs if d not in SKIP and not d.startswith("build"))
        for f in sorted(files):
            if f.endswith(endings):
                yield os.path.relpath(os.path.join(base, f), root)
