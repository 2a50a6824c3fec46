"""The idiom corpus's cases (issue 35, docs/DESIGN.md §10): every hooked
call the idioms program (tests/programs/idioms/) makes (CALL), from every context it can be
made from (CONTEXT), and for a signal handler's contexts, every call the
interrupted flow may be inside (INTERRUPTED); and the few Python idioms of
idioms.py. all_cases() is the whole cross product, sample(seed, n) a fixed
subset of it for the suite that still makes every CALL, every CONTEXT and
every INTERRUPTED at least once.

`python3 cases.py [--all | --seed S --count N]` lists cases, one a line."""

import argparse
import collections
import random

# the idioms program's calls (idioms/table.c) in its order, with their flags: posix (POSIX lists it
# as async-signal-safe), interrupted (a flow may loop over it while a
# handler interrupts it: a call that takes or reads time, so that a
# lockstep run's time moves: a device read on an fd kept open waits for
# its stream's next record, whereas one that opens the device afresh each
# time reads the record of the time it is at, and in lockstep a loop of
# those never waits), vfork (what a vfork child may do).
# run_corpus.py checks this against `idioms --list`.
CALLS = collections.OrderedDict((line.split()[0], set(line.split()[1:])) for line in """
clock_mono posix interrupted vfork
clock_real posix vfork
clock_process posix
clock_thread posix interrupted
gettimeofday interrupted
time posix
timespec_get
clock interrupted
times posix
getrusage
nanosleep interrupted
clock_nanosleep
clock_nanosleep_abs interrupted
usleep interrupted
sleep posix
thrd_sleep
select posix interrupted
pselect posix
poll posix interrupted
ppoll
epoll_wait interrupted
epoll_pwait
alarm posix
setitimer interrupted
getitimer interrupted
timer_create
timer_settime posix interrupted
timer_gettime posix interrupted
timer_getoverrun posix
timerfd
timerfd_gettime interrupted
timerfd_read interrupted
sigsuspend posix interrupted
pause posix interrupted
dev_read posix
dev_write posix
dev_fd posix interrupted
dev_fopen
kill posix
raise posix
sigqueue posix
tgkill
pidfd_send_signal
kill_child posix
sem_timedwait interrupted
sem_post posix
cond_timedwait
getrandom
urandom posix
fork posix
exec posix vfork
vfork
posix_spawn
system
socket posix
tcattr posix
dup posix
pipe_io
close_range
prctl
""".strip().splitlines())

INTERRUPTED = [c for c, f in CALLS.items() if "interrupted" in f]

# The calls that touch the physical world: natively /dev/tcs is absent, so
# a native run of such a case shows only that the program ran (its exit
# and its report), not what the device said.
DEVICE_CALLS = {"dev_read", "dev_write", "dev_fd", "dev_fopen", "py.dev_read", "py.dev_write"}

# The contexts, their variants after the slash (idioms/main.c's header).
C_CONTEXTS = ["main", "thread", "handler/itimer", "handler/posix", "nested/timer", "nested/kill", "fork", "vfork"]

# The Python idioms (idioms.py): a SIGALRM handler of signal.setitimer,
# and os.fork from a threaded program.
PY_CALLS = ["py.sleep", "py.monotonic", "py.dev_read", "py.dev_write", "py.setitimer"]
PY_INTERRUPTED = ["py.sleep", "py.monotonic", "py.pause"]
PY_FORK_CALLS = ["py.sleep", "py.monotonic", "py.dev_read", "py.setitimer"]
PY_CONTEXTS = ["py-handler", "py-fork"]

CONTEXTS = C_CONTEXTS + PY_CONTEXTS


class Case(collections.namedtuple("Case", "context call interrupted")):
    """One program run: CALL from CONTEXT (interrupting INTERRUPTED, or
    '-'). Its label is what run_corpus prints of it."""

    @property
    def python(self):
        return self.context.startswith("py-")

    @property
    def device(self):
        return self.call in DEVICE_CALLS or self.interrupted in DEVICE_CALLS

    def label(self):
        return "%s %s %s" % self

    def args(self):
        """The program's arguments (idioms or idioms.py)."""
        strip = (lambda s: s[3:]) if self.python else (lambda s: s)
        args = [strip(self.context), strip(self.call)]
        return args if self.interrupted == "-" else args + [strip(self.interrupted)]


def needs_own_itimer(call, interrupted):
    """Whether the case arms ITIMER_REAL itself, so that its SIGALRM
    driver must be a POSIX timer (idioms/main.c: alarm anywhere, setitimer in
    the interrupted flow)."""
    return "alarm" in (call, interrupted) or interrupted == "setitimer"


def handler_context(call, interrupted):
    """handler/itimer or handler/posix: the driver ITIMER_REAL where the
    case allows it, else a POSIX timer; which of the two where either will
    do alternates over the product, so each meets every call."""
    if needs_own_itimer(call, interrupted):
        return "handler/posix"
    names = list(CALLS)
    return ("handler/itimer", "handler/posix")[(names.index(call) + names.index(interrupted)) % 2]


def nested_context(call, interrupted):
    """nested/timer or nested/kill (where SIGUSR1 comes from), alternating
    over the product the other way from handler_context."""
    names = list(CALLS)
    return ("nested/timer", "nested/kill")[(names.index(call) + names.index(interrupted) + 1) % 2]


def all_cases():
    """The whole product, in a fixed order."""
    cases = []
    for call, flags in CALLS.items():
        cases += [Case("main", call, "-"), Case("thread", call, "-"), Case("fork", call, "-")]
        if "vfork" in flags:
            cases.append(Case("vfork", call, "-"))
        for flow in INTERRUPTED:
            cases.append(Case(handler_context(call, flow), call, flow))
            cases.append(Case(nested_context(call, flow), call, flow))
    for call in PY_CALLS:
        for flow in PY_INTERRUPTED:
            cases.append(Case("py-handler", call, flow))
    for call in PY_FORK_CALLS:
        cases.append(Case("py-fork", call, "-"))
    return cases


# The idioms issue 35 names, always in the sample: the control law in a
# SIGALRM handler while main pause()s; a handler re-arming its timer while
# main reads it; a handler that sleeps or reads clocks while main reads
# timers; fork from a program whose threads are inside timer hooks.
PINNED = [
    Case("handler/itimer", "dev_read", "pause"),
    Case("handler/itimer", "dev_write", "pause"),
    Case("handler/itimer", "setitimer", "getitimer"),
    Case("handler/posix", "timer_settime", "timer_gettime"),
    Case("nested/timer", "nanosleep", "timer_gettime"),
    Case("handler/posix", "setitimer", "clock_mono"),
    Case("fork", "setitimer", "-"),
    Case("fork", "nanosleep", "-"),
    Case("py-handler", "py.dev_read", "py.pause"),
    Case("py-fork", "py.sleep", "-"),
]


def sample(seed, n):
    """A fixed subset of about n cases (never fewer than coverage needs):
    the pinned idioms; then every CALL once, each in a context drawn in
    turn from a shuffled deck of the contexts that apply to it, so that
    every context comes up; then every INTERRUPTED and context that is
    still missing; then cases drawn from the rest of the product. The same
    seed gives the same cases."""
    rng = random.Random(seed)
    everything = all_cases()
    by_call_context = collections.defaultdict(list)
    for c in everything:
        by_call_context[(c.call, c.context.split("/")[0])].append(c)
    chosen = list(PINNED)

    deck = []

    def next_context(usable):
        # the first in the deck that applies; the deck is refilled shuffled
        for _ in range(2):
            for i, ctx in enumerate(deck):
                if ctx in usable:
                    return deck.pop(i)
            fresh = ["main", "thread", "handler", "nested", "fork"]
            rng.shuffle(fresh)
            deck.extend(fresh)
        return rng.choice(sorted(usable))

    calls = list(CALLS)
    rng.shuffle(calls)
    for call in calls:
        usable = {k[1] for k in by_call_context if k[0] == call}
        kind = next_context(usable)
        chosen.append(rng.choice(by_call_context[(call, kind)]))

    def have(pred):
        return any(pred(c) for c in chosen)

    for flow in INTERRUPTED + PY_INTERRUPTED:
        if not have(lambda c: c.interrupted == flow):
            chosen.append(rng.choice([c for c in everything if c.interrupted == flow]))
    for call in PY_CALLS + PY_FORK_CALLS:
        if not have(lambda c: c.call == call):
            chosen.append(rng.choice([c for c in everything if c.call == call]))
    for ctx in CONTEXTS:
        if not have(lambda c: c.context == ctx):
            chosen.append(rng.choice([c for c in everything if c.context == ctx]))
    rest = [c for c in everything if c not in set(chosen)]
    rng.shuffle(rest)
    chosen += rest[:max(0, n - len(chosen))]
    seen = set()
    return [c for c in chosen if not (c in seen or seen.add(c))]


# The suite's sample: its seed and size (run_corpus's defaults).
SEED = 35
COUNT = 120


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--all", action="store_true", help="the whole product")
    ap.add_argument("--seed", type=int, default=SEED)
    ap.add_argument("--count", type=int, default=COUNT)
    a = ap.parse_args()
    cases = all_cases() if a.all else sample(a.seed, a.count)
    for c in cases:
        print(c.label())
    kinds = collections.Counter(c.context for c in cases)
    print("# %d cases: %s" % (len(cases), ", ".join("%s %d" % kv for kv in sorted(kinds.items()))))


if __name__ == "__main__":
    main()
