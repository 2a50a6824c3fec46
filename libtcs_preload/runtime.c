/* The runtime's state (runtime.h): one struct every file reads, which
 * start-up (start.c) fills. It calls nothing: every other file stands on
 * it. */
#include "runtime.h"

struct tcs_runtime tcs_rt = { .state = TCS_OFF, .channel_fd = -1, .page_fd = -1 };
