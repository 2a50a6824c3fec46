/* What the preload says on stderr (report.c): one line each, "tcs: ...",
 * written with one system call (no stdio inside a hook). */
#ifndef TCS_PRELOAD_REPORT_H
#define TCS_PRELOAD_REPORT_H

#include "runtime.h"

/* Writes "tcs: " a b c "\n" to stderr in one write (any part may be NULL). */
void tcs_say(const char *a, const char *b, const char *c) TCS_HIDDEN;
/* Writes "tcs: <msg>\n" to stderr the first time it is called with *once == 0. */
void tcs_report_once(int *once, const char *msg) TCS_HIDDEN;

#endif
