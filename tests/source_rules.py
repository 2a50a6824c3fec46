"""Two rules of the source tree's layout (docs/ARCHITECTURE.md), checked on
the sources and on the objects a build made of them; fails, naming
FILE:LINE, on any file or header that breaks one:

 (a) No source file (.c .cc .h .py) is over 500 lines: past that, a file
     almost always holds two concerns, and is two files.
 (b) A header's functions are defined in one .c/.cc file: whoever reads a
     declaration finds its body in the one file named like it, and a file
     that grows is split along with its header, not behind it.

For (b) the header is read for the functions it declares without a body
(free functions, and class members, qualified by their namespaces and
classes); a function with a body in a header (inline, static inline,
constexpr, templates, members defined in their class or out of it) is
the header's own and is left out. Where each is defined comes from the
build, not from reading .cc files: `nm --defined-only -C` on every object
of BUILD_DIR/compile_commands.json, which names each object's source. Only
strong global definitions count (nm's T): a weak one (W) is an inline
function's copy, which every object using it may hold, except for a
function template declared in a header, whose explicit instantiations are
weak. Overloads count as one name: they too belong in one file.

Definitions are compared within each build target (library or program),
not across them: a target holding a header's functions in two of its
files breaks the rule, while two programs may each define a header's
functions in a file of their own (tests/fuzz/fuzz_target.h, which every
fuzz target implements, or a test's stand-in for a library function).

    source_rules.py [--rule lines|headers] SOURCE_ROOT BUILD_DIR

(both rules without --rule, as the suite runs them: test `source_rules`.)
"""

import collections
import json
import os
import re
import subprocess
import sys

from source_tree import project_files

MAX_LINES = 500
SOURCES = (".c", ".cc", ".h", ".py")
HEADERS = (".h",)


# ---- (a) length ----

def long_files(root):
    errors = []
    for f in project_files(root, SOURCES):
        with open(os.path.join(root, f), errors="replace") as text:
            n = sum(1 for _ in text)
        if n > MAX_LINES:
            errors.append("%s:%d: %d lines, over %d: split it along its concerns" % (f, MAX_LINES + 1, n, MAX_LINES))
    return errors


# ---- (b) a header's declarations ----

def blank_out(text):
    """The text with comments, string and character literals and
    preprocessor lines replaced by spaces (newlines kept, so that offsets
    still give line numbers; string quotes kept, so that extern "C" is
    still seen)."""
    out = list(text)
    i, n = 0, len(text)
    at_line_start = True
    while i < n:
        c = text[i]
        if c == "\n":
            at_line_start = True
            i += 1
            continue
        if at_line_start and c == "#":
            # A directive, with its continuation lines.
            while i < n and text[i] != "\n":
                if text[i] == "\\" and i + 1 < n and text[i + 1] == "\n":
                    i += 2
                    continue
                out[i] = " "
                i += 1
            continue
        if not c.isspace():
            at_line_start = False
        if text.startswith("//", i):
            while i < n and text[i] != "\n":
                out[i] = " "
                i += 1
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            for k in range(i, j):
                if out[k] != "\n":
                    out[k] = " "
            i = j
        elif c in "\"'":
            # R"(...)" raw strings: up to )delim"
            raw = c == '"' and i > 0 and text[i - 1] == "R"
            if raw:
                paren = text.find("(", i)
                end = text.find(")" + text[i + 1:paren] + '"', paren)
                j = n if end < 0 else end + len(text[i + 1:paren]) + 1
            else:
                j = i + 1
                while j < n and text[j] != c and text[j] != "\n":
                    j += 2 if text[j] == "\\" else 1
            for k in range(i + 1, min(j, n)):
                if out[k] != "\n":
                    out[k] = " "
            i = j + 1
        else:
            i += 1
    return "".join(out)


IDENT = r"[A-Za-z_]\w*"
# Words that end a declaration's name search, or make it no function.
NOT_NAMES = {"if", "while", "for", "switch", "return", "sizeof", "alignof", "decltype", "noexcept", "static_assert",
             "alignas", "__attribute__", "__declspec", "defined", "throw", "requires", "_Static_assert"}


def strip_attributes(s):
    """Removes __attribute__((...)), [[...]], alignas(...) and the
    like, whose parentheses would read as a parameter list."""
    s = re.sub(r"\[\[.*?\]\]", " ", s, flags=re.S)
    while True:
        m = re.search(r"\b(__attribute__|__declspec|alignas|__asm__|asm)\s*\(", s)
        if not m:
            return s
        depth, j = 0, m.end() - 1
        while j < len(s):
            depth += {"(": 1, ")": -1}.get(s[j], 0)
            j += 1
            if depth == 0:
                break
        s = s[:m.start()] + " " + s[j:]


def function_name(stmt):
    """The (possibly qualified) name a statement declares as a function,
    or None when it declares none: the identifier before the first
    top-level '(' that opens a parameter list."""
    stmt = strip_attributes(stmt)
    m = re.search(r"\boperator\b", stmt)
    if m:
        # operator==(, operator()(, operator bool(, operator new[](
        rest = stmt[m.end():]
        op = re.match(r"\s*(\(\)|\[\]|new\s*\[\]|delete\s*\[\]|[^\s\w(]+|" + IDENT + r"[\w\s:<>*&]*?)\s*\(", rest)
        if not op:
            return None
        before = re.search(r"((?:" + IDENT + r"\s*::\s*)*)$", stmt[:m.start()])
        return re.sub(r"\s+", "", before.group(1)) + "operator" + re.sub(r"\s+", "", op.group(1))
    depth = 0  # in <template arguments> or [an array's size]
    for i, c in enumerate(stmt):
        if c in "<[":
            depth += 1
        elif c in ">]":
            depth = max(0, depth - 1)
        elif c == "(" and depth == 0:
            m = re.search(r"(~?\s*" + IDENT + r"(?:\s*::\s*~?\s*" + IDENT + r")*)\s*$", stmt[:i])
            if not m:
                return None  # int (*fp)(int): a pointer, no function
            name = re.sub(r"\s+", "", m.group(1))
            if name.split("::")[-1].lstrip("~") in NOT_NAMES:
                return None
            if re.match(r"\s*[*&^]", stmt[i + 1:]):
                return None
            return name
    return None


# Statements that declare no function (a class template's declaration ends
# in "(class|struct)", a forward declaration in its name).
DECL_SKIP = re.compile(r"^\s*(typedef|using|friend|static_assert|_Static_assert|return|namespace"
                       r"|template\s*<[^;]*>\s*(class|struct)|(class|struct|union|enum)\s+" + IDENT + r"\s*$)\b")


def header_functions(text):
    """The functions a header declares without a body, and the names it
    defines: ({qualified name: (line, is_template)}, {names with bodies})."""
    code = blank_out(text)
    declared, defined = {}, set()
    # Scopes: ("ns", name), ("class", name), ("extern", None), ("skip", None).
    scopes = []
    templates = set()  # class templates: their members' instances are weak
    stmt_start = 0

    def qualify(name):
        if any(kind == "extern" for kind, _ in scopes) and "::" not in name:
            return name
        prefix = [n for kind, n in scopes if kind in ("ns", "class") and n]
        return "::".join(prefix + [name])

    def skipping():
        return any(kind == "skip" for kind, _ in scopes)

    i, n = 0, len(code)
    while i < n:
        c = code[i]
        if c not in "{};":
            i += 1
            continue
        stmt = code[stmt_start:i]
        if c == "{" and not skipping() and (stmt.count("(") > stmt.count(")") or stmt.rstrip().endswith("=")):
            # A braced value inside a statement (a default argument = {},
            # an initialiser): part of the statement, not a scope.
            depth = 0
            while i < n:
                depth += {"{": 1, "}": -1}.get(code[i], 0)
                i += 1
                if depth == 0:
                    break
            continue
        line = code.count("\n", 0, stmt_start + len(stmt) - len(stmt.lstrip())) + 1
        stmt_start = i + 1
        if c == "}":
            if scopes:
                scopes.pop()
            i += 1
            continue
        if skipping():
            if c == "{":
                scopes.append(("skip", None))
            i += 1
            continue
        # Labels (public:) belong to no statement.
        flat = " ".join(re.sub(r"\b(public|private|protected)\s*:(?!:)", " ", stmt).split())
        if c == "{":
            m = re.match(r"^(inline\s+)?namespace\s*(" + IDENT + r"(?:::" + IDENT + r")*)?\s*$", flat)
            if m:
                scopes.append(("ns", m.group(2)))
            elif re.match(r'^extern\s*"\s*"\s*$', flat):
                scopes.append(("extern", None))
            elif re.match(r"^(template\s*<.*>\s*)?(class|struct|union)\b", flat) and "(" not in flat.split(":")[0]:
                m = re.match(r"^(?:template\s*<.*>\s*)?(?:class|struct|union)\s+(?:\w+\s+)*?(" + IDENT +
                             r")\s*(final\s*)?(:|$)", flat)
                scopes.append(("class", m.group(1) if m else None))
                if m and flat.startswith("template"):
                    templates.add(m.group(1))
            else:
                name = function_name(flat) if not re.match(r"^(enum|typedef)\b", flat) else None
                if name and not re.search(r"=\s*$", flat):
                    defined.add(qualify(name))
                scopes.append(("skip", None))
            i += 1
            continue
        # c == ";": a declaration in a namespace, a class or extern "C".
        i += 1
        if not flat or DECL_SKIP.match(flat):
            continue
        name = function_name(flat)
        if not name:
            continue
        words = set(re.findall(IDENT, flat.split("(")[0]))
        if words & {"inline", "constexpr", "consteval"}:
            continue
        in_class = scopes and scopes[-1][0] == "class"
        if "static" in words and not in_class:
            continue  # internal to each file that includes it
        if re.search(r"\)\s*(const\s*)?(&&?\s*)?(noexcept\s*)?(override\s*)?=\s*(0|delete|default)\s*$", flat):
            continue
        if "=" in re.sub(r"\boperator\s*[^\s\w(]+", "operator", flat).split("(")[0]:
            continue  # a variable initialised with a call
        q = qualify(name)
        if q not in declared:
            declared[q] = (line, flat.startswith("template") or any(kind == "class" and cls in templates
                                                                     for kind, cls in scopes))
    return declared, defined


# ---- (b) where the build defines them ----

def symbol_name(demangled):
    """`tcs::McapWriter::open(std::string const&, ...) const` ->
    `tcs::McapWriter::open`: no parameters, template arguments, ABI tags
    or return type (which nm shows for template instances)."""
    s = re.sub(r"\[abi:\w+\]", "", demangled)
    out, depth, i = [], 0, 0
    while i < len(s):
        if s.startswith("operator", i) and (i == 0 or not (s[i - 1].isalnum() or s[i - 1] == "_")):
            m = re.match(r"operator\s*(\(\)|\[\]|new\[\]|delete\[\]|<=>|<<=|>>=|<<|>>|<=|>=|->\*|->"
                         r"|[^\s\w(]+|[\w:\s*&<>]+?(?=\())", s[i:])
            if m and depth == 0:
                out.append("operator" + re.sub(r"\s+", "", m.group(1)))
                i += m.end()
                continue
        c = s[i]
        if c == "<":
            depth += 1
        elif c == ">":
            depth -= 1
        elif c == "(" and depth == 0:
            break
        elif depth == 0:
            out.append(c)
        i += 1
    name = "".join(out).strip()
    # A return type first (template instances): the name is the last word
    # outside template arguments, which are gone by now.
    return re.sub(r"\s+", "", name.split(" ")[-1]) if " " in name and "operator" not in name else re.sub(
        r"\s+", "", name)


def object_sources(root, build):
    """{object path: source path relative to root} for every object the
    build has made of a source under root (compile_commands.json names
    each compilation's source and output)."""
    with open(os.path.join(build, "compile_commands.json")) as f:
        commands = json.load(f)
    objects = {}
    root = os.path.realpath(root)
    for c in commands:
        src = os.path.realpath(os.path.join(c["directory"], c["file"]))
        out = c.get("output")
        if out is None:  # older meson: the -o argument
            m = re.search(r"(?:^|\s)-o\s*(\S+)", c["command"])
            out = m.group(1) if m else None
        if out is None or not src.startswith(root + os.sep):
            continue  # generated sources are no one's to split
        obj = os.path.join(c["directory"], out)
        if os.path.exists(obj):
            objects[obj] = os.path.relpath(src, root)
    return objects


def target_of(obj, build):
    """meson puts a target's objects in BUILD/<folder>/<target>.p/."""
    rel = os.path.relpath(obj, build)
    parts = rel.split(os.sep)
    for k, p in enumerate(parts):
        if p.endswith(".p"):
            return "/".join(parts[:k + 1])[:-2]
    return os.path.dirname(rel)


def definitions(objects):
    """{(object, symbol name): {kinds}} for the global functions each
    object defines: 'T' (strong) or 'W' (weak)."""
    found = collections.defaultdict(set)
    names = sorted(objects)
    for k in range(0, len(names), 200):
        try:
            r = subprocess.run(["nm", "-A", "--defined-only", "-C"] + names[k:k + 200], capture_output=True,
                               text=True)
        except FileNotFoundError:
            raise SystemExit("source_rules.py: no nm (binutils) to read the objects with")
        if r.returncode != 0 and not r.stdout:
            raise SystemExit("nm failed: " + r.stderr.strip())
        for line in r.stdout.splitlines():
            # path.o:0000000000000000 T name(args)   (no address for some)
            m = re.match(r"^(.*?\.o):(?:[0-9a-fA-F]+)?\s+([TW])\s+(.*)$", line)
            if m:
                found[(m.group(1), symbol_name(m.group(3)))].add(m.group(2))
    return found


def split_headers(root, build):
    objects = object_sources(root, build)
    defs = definitions(objects)
    # symbol -> target -> {source: kinds}
    where = collections.defaultdict(lambda: collections.defaultdict(lambda: collections.defaultdict(set)))
    for (obj, name), kinds in defs.items():
        where[name][target_of(obj, build)][objects[obj]] |= kinds
    headers = list(project_files(root, HEADERS))
    parsed = {}
    all_defined = set()
    for h in headers:
        with open(os.path.join(root, h), errors="replace") as f:
            parsed[h] = header_functions(f.read())
        all_defined |= parsed[h][1]
    errors = []
    for h in headers:
        declared, _ = parsed[h]
        # target -> source -> [names]
        spread = collections.defaultdict(lambda: collections.defaultdict(list))
        for name, (line, template) in declared.items():
            if template and name in all_defined:
                continue  # its body is in a header (an inline one's copies are weak: never counted)
            for target, sources in where.get(name, {}).items():
                for src, kinds in sources.items():
                    if "T" in kinds or (template and "W" in kinds):
                        spread[target][src].append(name)
        for target, sources in sorted(spread.items()):
            if len(sources) < 2:
                continue
            # The line of the first declaration outside the file that holds most.
            main = max(sources, key=lambda s: len(sources[s]))
            others = [n for s in sources if s != main for n in sources[s]]
            line = min(declared[n][0] for n in others)
            errors.append("%s:%d: declares functions defined in %d files (in %s): each header's functions belong "
                          "in one .c/.cc file" % (h, line, len(sources), target))
            for src in sorted(sources, key=lambda s: (s != main, s)):
                errors.append("    %s: %s" % (src, ", ".join(sorted(sources[src]))))
    return errors, len(headers), len(objects)


def main(root, build, rule=None):
    if rule == "lines":
        errors = long_files(root)
        for e in errors:
            print(e)
        print("%d files over %d lines" % (len(errors), MAX_LINES))
        return 1 if errors else 0
    if not os.path.exists(os.path.join(build, "compile_commands.json")):
        print("%s: no compile_commands.json: not a meson build directory" % build, file=sys.stderr)
        return 2
    errors = long_files(root) if rule is None else []
    n_long = len(errors)
    split, n_headers, n_objects = split_headers(root, build)
    errors += split
    for e in errors:
        print(e)
    n_split = sum(1 for e in split if not e.startswith(" "))
    print("%d files over %d lines; %d of %d headers with functions defined in several files (%d objects read)" %
          (n_long, MAX_LINES, n_split, n_headers, n_objects))
    return 1 if errors else 0


if __name__ == "__main__":
    args = sys.argv[1:]
    rule = None
    if len(args) == 4 and args[0] == "--rule" and args[1] in ("lines", "headers"):
        rule = args[1]
        args = args[2:]
    if len(args) != 2:
        print("usage: source_rules.py [--rule lines|headers] SOURCE_ROOT BUILD_DIR", file=sys.stderr)
        sys.exit(2)
    sys.exit(main(args[0], args[1], rule))
