/* The seeded randomness of --seed (docs/DESIGN.md §2), shared by the
 * preload, which draws it, and the coordinator, which gives each
 * controller process its key: a stream of 8-byte blocks, block i of key k
 * a fixed function of (k, i), so that a process's draws repeat whatever the
 * machine. Each process has a key of its own (a child's is its parent's
 * key and its place among the parent's children), so children repeat too.
 * SplitMix64's finaliser mixes: statistically good, not cryptographic. */
#ifndef TCS_RANDOM_STREAM_H
#define TCS_RANDOM_STREAM_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

static inline uint64_t tcs_mix64(uint64_t z)
{
	z += 0x9e3779b97f4a7c15ull;
	z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
	z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
	return z ^ (z >> 31);
}

/* Block i of key's stream. */
static inline uint64_t tcs_random_block(uint64_t key, uint64_t i)
{
	return tcs_mix64(key ^ tcs_mix64(i));
}

/* The key of the nth process (1, 2, ...) derived from key: the nth
 * controller of a run seeded with key, or the nth child of a process with
 * that key. Never 0, which means no seed: real randomness. */
static inline uint64_t tcs_random_key(uint64_t key, uint64_t n)
{
	uint64_t k = tcs_mix64(tcs_mix64(key) ^ tcs_mix64(~n));
	return k ? k : 1;
}

#ifdef __cplusplus
}
#endif

#endif
