/* The idioms program: the calls that make processes, and those on descriptors (calls_processes.c). */
#ifndef TCS_IDIOMS_CALLS_PROCESSES_H
#define TCS_IDIOMS_CALLS_PROCESSES_H

#include "idioms.h"

void c_fork(struct ctx *c);
void c_exec(struct ctx *c);
void c_vfork(struct ctx *c);
void c_posix_spawn(struct ctx *c);
void c_system(struct ctx *c);
void c_socket(struct ctx *c);
void c_tcattr(struct ctx *c);
void c_dup(struct ctx *c);
void c_pipe_io(struct ctx *c);
void c_close_range(struct ctx *c);
void c_prctl(struct ctx *c);

#endif
