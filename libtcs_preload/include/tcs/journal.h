/* The journal (--record, --replay): what a controller's run depended on that
 * the machine decided, in the order the program met it: every clock value it
 * read and the virtual time of every request it made (docs/DESIGN.md §2).
 *
 * It lives in the controller's shared memory after the device table (the
 * clock page's journal_bytes say how much). Recording, it is a ring: the
 * controller appends (any thread: a slot is claimed, filled, then marked
 * with its kind), the coordinator drains it into the record at each request
 * and each stop, adding its own entries (stops, the end) in their place.
 * Replaying, it is a table the coordinator filled from the record before
 * the controller ran, which the controller walks with its own cursor. Nothing the controller writes here is trusted: the coordinator
 * reads each entry once, checks its kind, and bounds what it takes. */
#ifndef TCS_JOURNAL_H
#define TCS_JOURNAL_H

#include <stdint.h>

#include "device_table.h"

#ifdef __cplusplus
extern "C" {
#endif

#define TCS_JOURNAL_MAGIC 0x6e6a6374u /* "tcjn" */
/* Where the journal begins in the shared memory (after the device table). */
#define TCS_JOURNAL_OFFSET TCS_SHARED_SIZE
#define TCS_JOURNAL_HEADER 256
/* Recording: the ring's size (4 MiB: 174752 entries, more clock reads than
 * a program makes between two of its stops). */
#define TCS_JOURNAL_RING_BYTES (4u << 20)

enum tcs_journal_kind {
	TCS_J_CLOCK = 1,      /* a virtual clock read: value = V (ns, origin apart) */
	TCS_J_CPU = 2,        /* the process's CPU-time clock: value = what it read (ns) */
	TCS_J_THREAD_CPU = 3, /* a thread's CPU-time clock: value = what it read (ns) */
	TCS_J_CHARGE = 4,     /* a request (type = its TCS_MSG_*), or a wait that
			       * returned at once (type = TCS_MSG_BLOCK): value = the
			       * virtual time it was made at */
	TCS_J_READ = 5,       /* a read of a device: value = the virtual time it
			       * was made at, arg = what it returned (bytes, or
			       * -errno) */
	/* The coordinator's own, never a controller's: */
	TCS_J_STOP = 6,       /* the coordinator stopped it at value (a preemption:
			       * the world stepped there), arg = the real CPU it ran
			       * past its budget (the trace's overshoot) */
	TCS_J_EXIT = 7,       /* the process ended at value (its last slice's end) */
	TCS_J_KINDS = 8,
};

struct tcs_journal_entry {
	int64_t value;
	int64_t arg;
	uint16_t kind; /* 0: recording, not yet filled */
	uint16_t type;
	uint32_t thread; /* the thread's number in its process (0: the first) */
};

/* What the replaying controller says when it departs from the record: the
 * first call the record does not have. */
struct tcs_journal_departure {
	int64_t v;         /* its virtual time then */
	uint16_t kind;     /* what the program did (TCS_J_*) */
	uint16_t type;     /* and, for a request, its type */
	uint16_t expected_kind; /* what the record has there (0: nothing more) */
	uint16_t expected_type;
	int64_t expected_value;
	int64_t value;     /* what it read or asked, where that differs */
};

struct tcs_journal {
	uint32_t magic;
	uint32_t replaying; /* 0: a ring being recorded; 1: a table to replay */
	uint64_t capacity;  /* entries */
	/* Recording: the controller's next slot to claim. Replaying: its
	 * cursor, the next entry it takes. */
	uint64_t head __attribute__((aligned(64)));
	/* Recording: the coordinator's next slot to drain. Replaying: how
	 * many entries the table holds. */
	uint64_t tail __attribute__((aligned(64)));
	/* Recording: entries the controller could not append (the ring was
	 * full). */
	uint64_t lost;
	/* Replaying: 1 once it departed (then departure says where). */
	uint32_t departed;
	uint32_t reserved;
	struct tcs_journal_departure departure;
};

#if defined(__cplusplus)
static_assert(sizeof(struct tcs_journal) <= TCS_JOURNAL_HEADER, "journal header too large");
static_assert(sizeof(struct tcs_journal_entry) == 24, "entry layout");
#else
_Static_assert(sizeof(struct tcs_journal) <= TCS_JOURNAL_HEADER, "journal header too large");
_Static_assert(sizeof(struct tcs_journal_entry) == 24, "entry layout");
#endif

static inline struct tcs_journal_entry *tcs_journal_entries(struct tcs_journal *j)
{
	return (struct tcs_journal_entry *)((char *)j + TCS_JOURNAL_HEADER);
}

/* Bytes of shared memory a journal of n entries takes. */
static inline uint64_t tcs_journal_bytes(uint64_t n)
{
	return TCS_JOURNAL_HEADER + n * sizeof(struct tcs_journal_entry);
}

/* The trace's name for an entry's kind. */
static inline const char *tcs_journal_kind_name(unsigned kind)
{
	switch (kind) {
	case TCS_J_CLOCK: return "clock read";
	case TCS_J_CPU: return "CPU-time clock read";
	case TCS_J_THREAD_CPU: return "thread CPU-time clock read";
	case TCS_J_CHARGE: return "request";
	case TCS_J_READ: return "device read";
	case TCS_J_STOP: return "preemption";
	case TCS_J_EXIT: return "exit";
	default: return "end of the record";
	}
}

#ifdef __cplusplus
}
#endif
#endif
