/* hostile MODE: a controller that misuses its channel to the coordinator
 * the way a buggy or malicious program could (it writes to the runtime's
 * socket itself). MODE: garbage (48 random bytes), short (10 bytes), flood
 * (HELLO after HELLO), pid (a HELLO naming another process), block-twice
 * (two BLOCKs without waiting), huge (a BLOCK claiming 10^18 ns of CPU),
 * mailbox-garbage (48 random bytes posted in its clock page's mailbox, then
 * rung), mailbox-hello (a HELLO posted there, which only the channel may
 * carry), doorbell-flood (rings without posting).
 * It first runs a while, then misbehaves, then sleeps as if nothing
 * happened; the coordinator must drop it and go on with the others. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include "tcs/clock_page.h"
#include "tcs/protocol.h"
#include "tcs/vtime.h"

static int channel_fd(void)
{
	for (int fd = TCS_RUNTIME_FD_FLOOR; fd < TCS_RUNTIME_FD_FLOOR + 16; fd++) {
		int type = 0;
		socklen_t len = sizeof type;
		if (getsockopt(fd, SOL_SOCKET, SO_TYPE, &type, &len) == 0 && type == SOCK_SEQPACKET)
			return fd;
	}
	return -1;
}

/* The clock page, mapped again from the runtime's memfd. */
static struct tcs_clock_page *clock_page(void)
{
	for (int fd = TCS_RUNTIME_FD_FLOOR; fd < TCS_RUNTIME_FD_FLOOR + 16; fd++) {
		char link[64], target[128] = { 0 };
		snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
		if (readlink(link, target, sizeof target - 1) <= 0 || !strstr(target, "tcs-clock-page"))
			continue;
		void *p = mmap(NULL, TCS_PAGE_SIZE, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
		return p == MAP_FAILED ? NULL : p;
	}
	return NULL;
}

/* Posts len bytes as a request in the mailbox and rings. */
static int post(int fd, const void *request, size_t len)
{
	struct tcs_clock_page *page = clock_page();
	if (!page) {
		fprintf(stderr, "hostile: no clock page\n");
		return -1;
	}
	memcpy(&page->mailbox.request, request, len);
	__atomic_store_n(&page->mailbox.state, TCS_MBOX_REQUEST, __ATOMIC_SEQ_CST);
	struct tcs_msg ring = tcs_msg_make(TCS_MSG_DOORBELL, 0);
	send(fd, &ring, sizeof ring, 0);
	/* Until the coordinator has taken it (our own next sleep would post
	 * over it), spinning: any wait would be tcs's, through the mailbox.
	 * Seconds at most, then the coordinator has failed. */
	for (long i = 0; i < 1000000000L && (__atomic_load_n(&page->mailbox.state, __ATOMIC_ACQUIRE) & TCS_MBOX_REQUEST); i++)
		tcs_cpu_relax();
	return 0;
}

int main(int argc, char **argv)
{
	if (argc != 2) {
		fprintf(stderr, "usage: hostile garbage|short|flood|early-flood|pid|block-twice|huge|mailbox-garbage|mailbox-hello|doorbell-flood\n");
		return 2;
	}
	const char *mode = argv[1];
	struct timespec ms = { 0, 1000000 };
	for (int i = 0; i < 100; i++)
		nanosleep(&ms, NULL);
	int fd = channel_fd();
	if (fd < 0) {
		fprintf(stderr, "hostile: no channel (not under tcs-run?)\n");
		return 3;
	}
	struct tcs_msg m = tcs_msg_make(TCS_MSG_HELLO, 1000);
	m.arg = getpid();
	if (strcmp(mode, "garbage") == 0) {
		unsigned char junk[sizeof m];
		srand(42);
		for (size_t i = 0; i < sizeof junk; i++)
			junk[i] = (unsigned char)rand();
		send(fd, junk, sizeof junk, 0);
	} else if (strcmp(mode, "short") == 0) {
		send(fd, &m, 10, 0);
	} else if (strcmp(mode, "flood") == 0) {
		for (int i = 0; i < 100000; i++)
			if (send(fd, &m, sizeof m, MSG_DONTWAIT) < 0)
				break;
	} else if (strcmp(mode, "early-flood") == 0) {
		m = tcs_msg_make(TCS_MSG_EARLY, 3000);
		m.kind = TCS_EARLY_FD;
		for (int i = 0; i < 100000; i++)
			if (send(fd, &m, sizeof m, MSG_DONTWAIT) < 0)
				break;
	} else if (strcmp(mode, "pid") == 0) {
		m.arg = 1;
		send(fd, &m, sizeof m, 0);
	} else if (strcmp(mode, "block-twice") == 0 || strcmp(mode, "huge") == 0) {
		m = tcs_msg_make(TCS_MSG_BLOCK, 2000);
		m.kind = TCS_BLOCK_SLEEP;
		m.deadline = TCS_NEVER;
		if (strcmp(mode, "huge") == 0) {
			m.cpu = 1000000000000000000LL;
			m.v = 1000000000000000000LL;
			send(fd, &m, sizeof m, 0);
		} else {
			send(fd, &m, sizeof m, 0);
			m.seq++;
			send(fd, &m, sizeof m, 0);
		}
	} else if (strcmp(mode, "mailbox-garbage") == 0) {
		unsigned char junk[sizeof m];
		srand(42);
		for (size_t i = 0; i < sizeof junk; i++)
			junk[i] = (unsigned char)rand();
		if (post(fd, junk, sizeof junk) < 0)
			return 3;
	} else if (strcmp(mode, "mailbox-hello") == 0) {
		if (post(fd, &m, sizeof m) < 0)
			return 3;
	} else if (strcmp(mode, "doorbell-flood") == 0) {
		struct tcs_msg ring = tcs_msg_make(TCS_MSG_DOORBELL, 0);
		for (int i = 0; i < 100000; i++)
			if (send(fd, &ring, sizeof ring, MSG_DONTWAIT) < 0)
				break;
	} else {
		fprintf(stderr, "hostile: unknown mode %s\n", mode);
		return 2;
	}
	for (int i = 0; i < 2000; i++)
		nanosleep(&ms, NULL);
	printf("hostile: still here\n");
	return 0;
}
