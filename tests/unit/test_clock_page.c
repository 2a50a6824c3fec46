/* Unit tests for tcs/clock_page.h: the seqlock-protected slice, and the
 * virtual clock and CPU charge a controller derives from it. */
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <time.h>

#include <cmocka.h>

#include <tcs/clock_page.h>

#include "test_i64.h"

static struct tcs_clock_page page;

static void page_init(struct tcs_clock_page *p, enum tcs_mode mode, double scale)
{
	memset(p, 0, sizeof *p);
	p->magic = TCS_PAGE_MAGIC;
	p->version = TCS_PAGE_VERSION;
	p->mode = (uint32_t)mode;
	p->cpu_scale = scale;
}

static struct tcs_slice slice_make(int64_t v_base, int64_t cpu_base, int64_t charged_base)
{
	struct tcs_slice s = { 0 };
	s.v_base = v_base;
	s.cpu_base = cpu_base;
	s.charged_base = charged_base;
	return s;
}

static void assert_slice_eq(struct tcs_slice got, struct tcs_slice want)
{
	assert_i64_eq(got.v_base, want.v_base);
	assert_i64_eq(got.cpu_base, want.cpu_base);
	assert_i64_eq(got.charged_base, want.charged_base);
}

static void sleep_ms(long ms)
{
	struct timespec ts = { ms / 1000, (ms % 1000) * 1000000L };
	while (nanosleep(&ts, &ts) != 0)
		;
}

/* ---- seqlock write/read ---------------------------------------------------- */

static void test_write_read_round_trip(void **state)
{
	page_init(&page, TCS_MODE_CPU, 1.0);
	assert_slice_eq(tcs_page_read_slice(&page), slice_make(0, 0, 0));

	struct tcs_slice a = slice_make(5000000000LL, 123456789, 42);
	tcs_page_write_slice(&page, a);
	assert_slice_eq(tcs_page_read_slice(&page), a);
	assert_int_equal(page.seq, 2); /* even: no write in progress */

	struct tcs_slice b = slice_make(TCS_NEVER, INT64_MAX - 1, TCS_NEVER - 7);
	tcs_page_write_slice(&page, b);
	assert_slice_eq(tcs_page_read_slice(&page), b);
	assert_int_equal(page.seq, 4);

	/* The writer touches only the slice and seq. */
	assert_int_equal(page.magic, TCS_PAGE_MAGIC);
	assert_int_equal(page.mode, TCS_MODE_CPU);
	assert_true(page.cpu_scale == 1.0);
	assert_i64_eq(page.exit_cpu, 0);
}

static void test_seq_wraps_around(void **state)
{
	page_init(&page, TCS_MODE_CPU, 1.0);
	page.seq = UINT32_MAX - 1;
	tcs_page_write_slice(&page, slice_make(1, 2, 3));
	assert_int_equal(page.seq, 0);
	assert_slice_eq(tcs_page_read_slice(&page), slice_make(1, 2, 3));
	tcs_page_write_slice(&page, slice_make(4, 5, 6));
	assert_int_equal(page.seq, 2);
	assert_slice_eq(tcs_page_read_slice(&page), slice_make(4, 5, 6));
}

static int odd_reader_done;
static struct tcs_slice odd_reader_result;

static void *odd_reader(void *arg)
{
	odd_reader_result = tcs_page_read_slice(&page);
	__atomic_store_n(&odd_reader_done, 1, __ATOMIC_RELEASE);
	return NULL;
}

/* While seq is odd (a write in progress) a reader must not return the
 * half-written slice; it returns the complete one once seq is even. */
static void test_reader_waits_for_writer(void **state)
{
	page_init(&page, TCS_MODE_CPU, 1.0);
	tcs_page_write_slice(&page, slice_make(1, 1, 1));
	/* A writer stopped halfway: seq odd, one field updated. */
	__atomic_store_n(&page.seq, page.seq + 1, __ATOMIC_RELAXED);
	__atomic_store_n(&page.slice.v_base, 7, __ATOMIC_RELAXED);
	odd_reader_done = 0;

	pthread_t t;
	assert_int_equal(pthread_create(&t, NULL, odd_reader, NULL), 0);
	/* A reader that took the half-written slice would be done within
	 * microseconds: 50 ms is thousands of its tries. */
	sleep_ms(50);
	assert_int_equal(__atomic_load_n(&odd_reader_done, __ATOMIC_ACQUIRE), 0);

	__atomic_store_n(&page.slice.cpu_base, 8, __ATOMIC_RELAXED);
	__atomic_store_n(&page.slice.charged_base, 9, __ATOMIC_RELAXED);
	__atomic_store_n(&page.seq, page.seq + 1, __ATOMIC_RELEASE);
	assert_int_equal(pthread_join(t, NULL), 0);
	assert_int_equal(odd_reader_done, 1);
	assert_slice_eq(odd_reader_result, slice_make(7, 8, 9));
}

/* ---- tcs_page_vnow / tcs_page_charged ------------------------------------- */

static void test_vnow_lockstep_ignores_cpu(void **state)
{
	page_init(&page, TCS_MODE_LOCKSTEP, 1.0);
	struct tcs_slice s = slice_make(5000000000LL, 1000000, 7);
	tcs_page_write_slice(&page, s);
	s = tcs_page_read_slice(&page);
	static const int64_t cpus[] = { 0, 999999, 1000000, 1000001, 2000000000LL, INT64_MAX };
	static const int64_t exits[] = { 0, 1000500, INT64_MAX, INT64_MIN };
	for (size_t e = 0; e < sizeof exits / sizeof exits[0]; e++) {
		page.exit_cpu = exits[e];
		for (size_t i = 0; i < sizeof cpus / sizeof cpus[0]; i++)
			assert_i64_eq(tcs_page_vnow(&page, s, cpus[i]), 5000000000LL);
	}
	/* Even an absurd scale changes nothing. */
	page.cpu_scale = 1e6;
	page.exit_cpu = 0;
	assert_i64_eq(tcs_page_vnow(&page, s, 3000000000LL), 5000000000LL);
}

static void test_vnow_cpu_mode(void **state)
{
	page_init(&page, TCS_MODE_CPU, 1.0);
	struct tcs_slice s = slice_make(1000000000LL, 500000, 0);
	tcs_page_write_slice(&page, s);
	s = tcs_page_read_slice(&page);

	/* Stale mark (before the base): all CPU since the base counts. */
	page.exit_cpu = 0;
	assert_i64_eq(tcs_page_vnow(&page, s, 500000), 1000000000LL);
	assert_i64_eq(tcs_page_vnow(&page, s, 800000), 1000300000LL);
	/* Mark after the base: the hook's cost (base..mark) is excluded. */
	page.exit_cpu = 600000;
	assert_i64_eq(tcs_page_vnow(&page, s, 800000), 1000200000LL);
	assert_i64_eq(tcs_page_vnow(&page, s, 600000), 1000000000LL);
	/* Mark beyond now: nothing yet. */
	page.exit_cpu = 900000;
	assert_i64_eq(tcs_page_vnow(&page, s, 800000), 1000000000LL);
	page.exit_cpu = INT64_MAX;
	assert_i64_eq(tcs_page_vnow(&page, s, 800000), 1000000000LL);
	/* CPU clock before the base. */
	page.exit_cpu = 0;
	assert_i64_eq(tcs_page_vnow(&page, s, 100), 1000000000LL);

	/* Scaled. */
	page.exit_cpu = 600000;
	page.cpu_scale = 3.0;
	assert_i64_eq(tcs_page_vnow(&page, s, 800000), 1000600000LL);
	page.cpu_scale = 0.5;
	assert_i64_eq(tcs_page_vnow(&page, s, 800001), 1000100000LL); /* 100000.5 rounded down */
	assert_i64_eq(tcs_page_vnow(&page, s, 800003), 1000100001LL);
}

static void test_vnow_cpu_mode_saturates(void **state)
{
	page_init(&page, TCS_MODE_CPU, 1.0);
	struct tcs_slice s = slice_make(TCS_NEVER - 10, 0, 0);
	tcs_page_write_slice(&page, s);
	assert_i64_eq(tcs_page_vnow(&page, s, 5), TCS_NEVER - 5);
	assert_i64_eq(tcs_page_vnow(&page, s, 10), TCS_NEVER);
	assert_i64_eq(tcs_page_vnow(&page, s, 1000000), TCS_NEVER);
	assert_i64_eq(tcs_page_vnow(&page, s, INT64_MAX), TCS_NEVER);
	page.cpu_scale = 1e9;
	s = slice_make(0, 0, 0);
	assert_i64_eq(tcs_page_vnow(&page, s, INT64_MAX / 2), TCS_NEVER);
}

static void test_charged_both_modes(void **state)
{
	static const enum tcs_mode modes[] = { TCS_MODE_CPU, TCS_MODE_LOCKSTEP };
	for (size_t m = 0; m < 2; m++) {
		page_init(&page, modes[m], 1.0);
		struct tcs_slice s = slice_make(9000000000LL, 2000000, 300000);
		tcs_page_write_slice(&page, s);
		s = tcs_page_read_slice(&page);

		page.exit_cpu = 0;
		assert_i64_eq(tcs_page_charged(&page, s, 2000000), 300000);
		assert_i64_eq(tcs_page_charged(&page, s, 2500000), 800000);
		page.exit_cpu = 2100000; /* hook cost excluded */
		assert_i64_eq(tcs_page_charged(&page, s, 2500000), 700000);
		page.exit_cpu = INT64_MAX; /* lying mark */
		assert_i64_eq(tcs_page_charged(&page, s, 2500000), 300000);
		page.exit_cpu = 2100000;
		page.own_cpu = 50000; /* the runtime's clock reads excluded */
		assert_i64_eq(tcs_page_charged(&page, s, 2500000), 650000);
		page.own_cpu = INT64_MAX; /* a lying credit */
		assert_i64_eq(tcs_page_charged(&page, s, 2500000), 300000);
		page.own_cpu = 0;
		page.cpu_scale = 3.0;
		assert_i64_eq(tcs_page_charged(&page, s, 2500000), 1500000);
		page.cpu_scale = 0.5;
		assert_i64_eq(tcs_page_charged(&page, s, 2500001), 500000);
		assert_i64_eq(tcs_page_charged(&page, s, 100), 300000);
		/* The charge never depends on the virtual clock. */
		s.v_base = 0;
		assert_i64_eq(tcs_page_charged(&page, s, 2500001), 500000);
		s.charged_base = TCS_NEVER - 1;
		assert_i64_eq(tcs_page_charged(&page, s, INT64_MAX), TCS_NEVER);
	}
}

/* Whatever the controller wrote as its mark and whatever its CPU clock says,
 * its clock and charge never fall below where the coordinator put them. */
static void test_never_below_base(void **state)
{
	static const double scales[] = { 1.0, 3.0, 0.5, 0.37, 1e-9, 1e9 };
	uint64_t rng = 0xc0ffee;
	for (int i = 0; i < 200000; i++) {
		page_init(&page, (i & 1) ? TCS_MODE_CPU : TCS_MODE_LOCKSTEP, scales[i % 6]);
		struct tcs_slice s = slice_make((int64_t)(test_rand(&rng) >> 1), (int64_t)(test_rand(&rng) >> 1),
						(int64_t)(test_rand(&rng) >> 1));
		page.exit_cpu = (int64_t)test_rand(&rng);
		int64_t cpu = (int64_t)test_rand(&rng);
		if (i & 2) { /* keep everything near the base so all orderings occur */
			page.exit_cpu = s.cpu_base + (int64_t)(test_rand(&rng) % 2001) - 1000;
			cpu = s.cpu_base + (int64_t)(test_rand(&rng) % 2001) - 1000;
		}
		assert_i64_ge(tcs_page_vnow(&page, s, cpu), s.v_base);
		assert_i64_ge(tcs_page_charged(&page, s, cpu), s.charged_base);
	}
}

/* ---- monotonicity across slices ------------------------------------------- */

enum exit_behaviour {
	EXIT_HONEST,  /* mark = CPU when the hook returned, as the preload does */
	EXIT_STALE,   /* never updated after the first slice */
	EXIT_FUTURE,  /* a lie: some time beyond now */
	EXIT_MAX,     /* a lie: INT64_MAX */
	EXIT_NEGATIVE, /* a lie: negative */
	EXIT_RANDOM,  /* any of the above, chosen per slice */
	EXIT_COUNT,
};

static int64_t rand_below(uint64_t *rng, int64_t n)
{
	return (int64_t)(test_rand(rng) % (uint64_t)n);
}

/* Runs a controller through many slices, with the coordinator's side done as
 * the coordinator does it: at the end of each slice the virtual time is what
 * the page gives at that moment, a wait moves it on, and the next slice starts
 * there with the CPU clock at that moment as its base. Every clock read by the
 * controller must be >= the previous one and >= the WAKE time it last got. */
static void run_slices(enum tcs_mode mode, double scale, enum exit_behaviour how, int64_t v0, uint64_t seed)
{
	uint64_t rng = seed;
	page_init(&page, mode, scale);
	int64_t cpu = 1000000; /* the process's real CPU clock */
	int64_t last_v = v0, last_charged = 0;
	tcs_page_write_slice(&page, slice_make(v0, cpu, 0));

	for (int k = 0; k < 2000; k++) {
		/* The hook returns after the WAKE; the mark is written once. */
		cpu += rand_below(&rng, 5000);
		enum exit_behaviour h = how == EXIT_RANDOM ? (enum exit_behaviour)rand_below(&rng, EXIT_RANDOM) : how;
		switch (h) {
		case EXIT_HONEST:
			__atomic_store_n(&page.exit_cpu, cpu, __ATOMIC_RELAXED);
			break;
		case EXIT_STALE:
			if (k == 0)
				__atomic_store_n(&page.exit_cpu, cpu, __ATOMIC_RELAXED);
			break;
		case EXIT_FUTURE:
			__atomic_store_n(&page.exit_cpu, cpu + 1 + rand_below(&rng, 20000000), __ATOMIC_RELAXED);
			break;
		case EXIT_MAX:
			__atomic_store_n(&page.exit_cpu, INT64_MAX, __ATOMIC_RELAXED);
			break;
		case EXIT_NEGATIVE:
			__atomic_store_n(&page.exit_cpu, -1 - rand_below(&rng, INT64_MAX), __ATOMIC_RELAXED);
			break;
		default:
			break;
		}

		/* The program runs and reads its clocks. */
		int reads = (int)rand_below(&rng, 8);
		for (int r = 0; r < reads; r++) {
			cpu += rand_below(&rng, 2000000);
			struct tcs_slice s = tcs_page_read_slice(&page);
			int64_t v = tcs_page_vnow(&page, s, cpu);
			int64_t ch = tcs_page_charged(&page, s, cpu);
			assert_i64_ge(v, last_v);
			assert_i64_ge(ch, last_charged);
			if (mode == TCS_MODE_LOCKSTEP)
				assert_i64_eq(v, s.v_base);
			last_v = v;
			last_charged = ch;
		}

		/* It blocks; the coordinator ends the slice. */
		cpu += rand_below(&rng, 3000);
		struct tcs_slice s = tcs_page_read_slice(&page);
		int64_t v_end = tcs_page_vnow(&page, s, cpu);
		int64_t charged_end = tcs_page_charged(&page, s, cpu);
		assert_i64_ge(v_end, last_v);
		assert_i64_ge(charged_end, last_charged);
		/* The wait: sometimes a deadline already passed, sometimes a sleep. */
		int64_t wait = rand_below(&rng, 4) == 0 ? 0 : rand_below(&rng, 2000000000LL);
		int64_t v_wake = tcs_ns_add(v_end, wait);
		tcs_page_write_slice(&page, slice_make(v_wake, cpu, charged_end));
		last_v = v_wake;
		last_charged = charged_end;
	}
}

static void test_monotonic_across_slices(void **state)
{
	static const double scales[] = { 1.0, 3.0, 0.5, 0.37, 1e-6, 1000.0 };
	static const int64_t starts[] = { 0, 1714564800000000000LL, TCS_NEVER - 3000000000LL };
	uint64_t seed = 1;
	for (int mode = 0; mode < 2; mode++)
		for (size_t sc = 0; sc < sizeof scales / sizeof scales[0]; sc++)
			for (int how = 0; how < EXIT_COUNT; how++)
				for (size_t st = 0; st < sizeof starts / sizeof starts[0]; st++)
					run_slices(mode ? TCS_MODE_LOCKSTEP : TCS_MODE_CPU, scales[sc],
						   (enum exit_behaviour)how, starts[st], seed++);
}

/* ---- concurrency: no torn reads ------------------------------------------- */

#define CONC_MAX_WRITES 1000000000ULL
#define CONC_MIN_READS 10000ULL

static struct tcs_clock_page conc_page;
static int conc_stop;
static int conc_writer_done;
static uint64_t conc_writes;
static uint64_t conc_reads;
static uint64_t conc_torn;
static uint64_t conc_backwards;
static uint64_t conc_changes;
static struct tcs_slice conc_final;

/* Publishes slices with v_base == cpu_base == charged_base in a tight loop
 * until told to stop and the reader has read enough while it was writing. */
static void *conc_writer(void *arg)
{
	uint64_t n = 0;
	while (n < CONC_MAX_WRITES) {
		if ((n & 1023) == 0 && __atomic_load_n(&conc_stop, __ATOMIC_ACQUIRE) &&
		    __atomic_load_n(&conc_reads, __ATOMIC_RELAXED) >= CONC_MIN_READS)
			break;
		n++;
		tcs_page_write_slice(&conc_page, slice_make((int64_t)n, (int64_t)n, (int64_t)n));
		/* Back-to-back writes half the time; otherwise a short, varying
		 * gap so that the reader also completes reads between writes. */
		if (n & 1)
			for (unsigned k = (unsigned)(n >> 1) % 16; k > 0; k--)
				tcs_cpu_relax();
	}
	conc_writes = n;
	__atomic_store_n(&conc_writer_done, 1, __ATOMIC_RELEASE);
	return NULL;
}

static void *conc_reader(void *arg)
{
	uint64_t reads = 0, torn = 0, backwards = 0, changes = 0;
	int64_t last = 0;
	for (;;) {
		int done = __atomic_load_n(&conc_writer_done, __ATOMIC_ACQUIRE);
		struct tcs_slice s = tcs_page_read_slice(&conc_page);
		if (s.v_base != s.cpu_base || s.cpu_base != s.charged_base)
			torn++;
		if (s.v_base < last)
			backwards++;
		if (s.v_base != last)
			changes++;
		last = s.v_base;
		__atomic_store_n(&conc_reads, ++reads, __ATOMIC_RELAXED);
		if (done) {
			conc_final = s;
			break;
		}
	}
	conc_torn = torn;
	conc_backwards = backwards;
	conc_changes = changes;
	return NULL;
}

static void test_concurrent_reads_never_torn(void **state)
{
	page_init(&conc_page, TCS_MODE_CPU, 1.0);
	pthread_t w, r;
	assert_int_equal(pthread_create(&r, NULL, conc_reader, NULL), 0);
	assert_int_equal(pthread_create(&w, NULL, conc_writer, NULL), 0);
	sleep_ms(200);
	__atomic_store_n(&conc_stop, 1, __ATOMIC_RELEASE);
	assert_int_equal(pthread_join(w, NULL), 0);
	assert_int_equal(pthread_join(r, NULL), 0);

	print_message("      %llu writes, %llu reads, %llu distinct values seen\n", (unsigned long long)conc_writes,
		      (unsigned long long)conc_reads, (unsigned long long)conc_changes);
	assert_true(conc_reads >= CONC_MIN_READS);
	assert_true(conc_writes > 0);
	assert_int_equal(conc_torn, 0);
	assert_int_equal(conc_backwards, 0);
	/* The read after the writer finished sees its last slice. */
	assert_slice_eq(conc_final, slice_make((int64_t)conc_writes, (int64_t)conc_writes, (int64_t)conc_writes));
	assert_int_equal(conc_page.seq, (uint32_t)(2 * conc_writes));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_write_read_round_trip),
		cmocka_unit_test(test_seq_wraps_around),
		cmocka_unit_test(test_reader_waits_for_writer),
		cmocka_unit_test(test_vnow_lockstep_ignores_cpu),
		cmocka_unit_test(test_vnow_cpu_mode),
		cmocka_unit_test(test_vnow_cpu_mode_saturates),
		cmocka_unit_test(test_charged_both_modes),
		cmocka_unit_test(test_never_below_base),
		cmocka_unit_test(test_monotonic_across_slices),
		cmocka_unit_test(test_concurrent_reads_never_torn),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
