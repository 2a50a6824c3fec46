"""The processes of a session, read from /proc: what the tests and the
idiom corpus's runner (tests/corpus/run_corpus.py) check is left of a run."""

import os


def session_processes(sid):
    """(pid, state, command) of every process in session sid."""
    found = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open("/proc/%s/stat" % entry) as f:
                stat = f.read()
        except OSError:
            continue
        rest = stat[stat.rindex(")") + 2:].split()
        if int(rest[3]) == sid:
            found.append((int(entry), rest[0], stat[stat.index("(") + 1:stat.rindex(")")]))
    return found
