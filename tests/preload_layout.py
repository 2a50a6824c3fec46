"""The preload's layout is its architecture (docs/ARCHITECTURE.md): fails,
naming FILE:LINE, where libtcs_preload/ parts from it.

- a header declares functions of one .c file only, the one it is named
  after (static inline helpers aside);
- every exported hook (TCS_EXPORT) is in a hooks_*.c file;
- hooks call down into the runtime, never the reverse: no file but a
  hooks_*.c one calls a function a hooks_*.c file defines;
- no lock but spin_lock.h's, which blocks signals while held: nothing
  else spins on an atomic exchange, and nothing takes a pthread lock (a
  signal handler's hook would find it held by the flow it interrupted);
- the fd table (fd_table.c) is the only table per fd: no other file has an
  array sized by TCS_FD_MAX, and the table itself takes no lock (a
  handler's hook reads it while the flow it interrupted writes it);
- no hook file names a kind of fd (TCS_DEVICE_SERIAL, TCS_FD_CAN, ...): a
  hook calls the operations the fd's entry names, and only the kinds'
  own files, and device_open.c's map from device kind to operations,
  choose by kind.

    preload_layout.py SOURCE_ROOT
"""

import os
import re
import sys

IDENT = r"[A-Za-z_]\w*"
# A function declared or defined at the start of a line: its name, then "(".
FUNCTION = re.compile(r"^(?!static\b|#|\s|typedef\b|extern\b|struct\b[^(]*\{|enum\b|union\b|[}/*])"
                      r"[^=;{(]*?\b(" + IDENT + r")\s*\(")


def strip_comments(text):
    """The text with comments blanked (newlines kept, for line numbers)."""
    return re.sub(r"/\*.*?\*/|//[^\n]*", lambda m: re.sub(r"[^\n]", " ", m.group(0)), text, flags=re.S)


def top_level_functions(text):
    """(name, line, is_definition) for each function declared or defined
    outside any braces, static ones left out."""
    out = []
    lines = text.split("\n")
    depth = 0
    for n, line in enumerate(lines, 1):
        if depth == 0:
            m = FUNCTION.match(line)
            if m and not line.startswith("static"):
                # A definition's body opens before the next ";".
                rest = "\n".join(lines[n - 1:n + 8])
                semi, brace = rest.find(";"), rest.find("{")
                is_def = brace >= 0 and (semi < 0 or brace < semi)
                out.append((m.group(1), n, is_def))
        depth += line.count("{") - line.count("}")
    return out


def main(root):
    folder = os.path.join(root, "libtcs_preload")
    names = sorted(f for f in os.listdir(folder) if f.endswith((".c", ".h")))
    texts = {}
    for f in names:
        with open(os.path.join(folder, f)) as src:
            texts[f] = src.read()
    errors = []
    defined_in = {}  # function -> the .c file that defines it
    for f in names:
        if f.endswith(".c"):
            for name, n, is_def in top_level_functions(strip_comments(texts[f])):
                if is_def:
                    defined_in.setdefault(name, f)
    for f in names:
        path = "libtcs_preload/" + f
        code = strip_comments(texts[f])
        if f.endswith(".h"):
            own = f[:-2] + ".c"
            for name, n, is_def in top_level_functions(code):
                where = defined_in.get(name)
                if not is_def and where is not None and where != own:
                    errors.append("%s:%d: declares %s, defined in %s (a header declares its own .c file's functions)"
                                  % (path, n, name, where))
        else:
            lines = code.split("\n")
            for name, n, is_def in top_level_functions(code):
                if is_def and "TCS_EXPORT" in lines[n - 1] and not f.startswith("hooks_"):
                    errors.append("%s:%d: exports %s outside a hooks_*.c file" % (path, n, name))
            if not f.startswith("hooks_"):
                for name, where in defined_in.items():
                    if where.startswith("hooks_") and name.startswith("tcs_"):
                        for n, line in enumerate(code.split("\n"), 1):
                            if re.search(r"\b%s\s*\(" % re.escape(name), line):
                                errors.append("%s:%d: calls %s of %s: the runtime calls no hook file" % (path, n, name, where))
    for f in names:
        # spin_lock.h is the lock; timer_thread.c's mutex is only ever held
        # with every signal blocked (its helper threads block them all, and
        # tcs_timer_threads_poke around it). A program's own mutex, which
        # the hooks try through tcs_real_fns, is no lock of ours.
        if f in ("spin_lock.h", "timer_thread.c"):
            continue
        for n, line in enumerate(strip_comments(texts[f]).split("\n"), 1):
            if re.search(r"while\s*\(\s*__atomic_(exchange|test_and_set)|(?<![.\w])pthread_(mutex|spin|rwlock)_(lock|trylock|wrlock|rdlock)\s*\(", line):
                errors.append("libtcs_preload/%s:%d: a lock other than spin_lock.h's tcs_lock, which blocks signals "
                              "while held (docs/DESIGN.md, \"Re-entrancy\")" % (f, n))
    for f in names:
        code = strip_comments(texts[f])
        for n, line in enumerate(code.split("\n"), 1):
            if f not in ("fd_table.c", "fd_table.h") and re.search(r"\[[^\]]*\bTCS_FD_MAX\b[^\]]*\]", line):
                errors.append("libtcs_preload/%s:%d: a table per fd beside fd_table.c's: an fd's state is its entry's "
                              "(struct tcs_fd: the kind's slot)" % (f, n))
            if f.startswith("hooks_") and re.search(r"\bTCS_(DEVICE|FD)_(SENSOR|ACTUATOR|SERIAL|I2C|CAN|TIMERFD|RANDOM)\b",
                                                    line):
                errors.append("libtcs_preload/%s:%d: a hook chooses by kind of fd: it calls the operations of the "
                              "fd's entry (fd_table.h) instead" % (f, n))
            if f == "fd_table.c" and re.search(r"\btcs_(lock|locks_hold_all)\s*\(", line):
                errors.append("libtcs_preload/%s:%d: the fd table takes a lock: a handler's hook reading it "
                              "would wait for the flow it interrupted" % (f, n))
    for e in errors:
        print(e)
    print("%d files, %d problems" % (len(names), len(errors)))
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "."))
