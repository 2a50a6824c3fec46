"""--seed's stream across exec and through dup'd fds (docs/DESIGN.md §2,
Seeded randomness): a process's randomness is block i of its key's stream,
taken in order a block per 8 bytes (or part) of each call, the position
kept in its clock page, so an exec'd image goes on where its predecessor
stopped; a dup (or dup2) of an fd of /dev/urandom draws from the stream as
the original does, and still after the original is closed.

The expected bytes are computed here from the stream's definition
(libtcs_preload/include/tcs/random_stream.h: SplitMix64's finaliser; the
first controller of a run seeded with N has the key of process 1 of N),
not read from tcs."""

from harness import check, main, prog, tcs

M64 = (1 << 64) - 1


def mix64(z):
    z = (z + 0x9e3779b97f4a7c15) & M64
    z = ((z ^ (z >> 30)) * 0xbf58476d1ce4e5b9) & M64
    z = ((z ^ (z >> 27)) * 0x94d049bb133111eb) & M64
    return z ^ (z >> 31)


def key_of(key, n):
    """The key of the nth process derived from key (never 0)."""
    return mix64(mix64(key) ^ mix64(~n & M64)) or 1


def block(key, i):
    """Block i of key's stream, as its 8 bytes (least significant first)."""
    return mix64(key ^ mix64(i)).to_bytes(8, "little")


def expected(seed):
    """What tests/programs/seed_exec prints, call by call: each call takes
    the next blocks, as many as its bytes need."""
    key = key_of(seed, 1)
    draws = [("getrandom", 8), ("dup", 8), ("dup2", 8), ("after_close", 8), ("odd", 12), ("readv", (4, 8)),
             ("exec_getrandom", 8), ("exec_short", 3)]
    at, out = 0, {}
    for name, sizes in draws:
        data = b""
        for n in sizes if isinstance(sizes, tuple) else (sizes,):  # readv: a call's fill per buffer
            blocks = b"".join(block(key, at + k) for k in range((n + 7) // 8))
            data += blocks[:n]
            at += (n + 7) // 8
        out[name] = data.hex()
    return out


def test_the_stream_goes_on_across_exec_and_dup():
    for seed in (42, 7):
        for mode in ("lockstep", "cpu"):
            r = tcs("-q", "-m", mode, "--seed", str(seed), prog("seed_exec"), timeout=60)
            v = r.values()
            check(r.returncode == 0, "seed %d, %s: seed_exec runs and execs" % (seed, mode), r)
            want = expected(seed)
            for name, hexed in want.items():
                check(v.get(name) == hexed, "seed %d, %s: %s draws the stream's next bytes %s: %s" %
                      (seed, mode, name, hexed, v.get(name)), r)


if __name__ == "__main__":
    main(globals())
