// What /proc says of a process that is not ours to wait for: its parent,
// its program's name, its exit status while a zombie, whether it sleeps.
#pragma once

#include <sys/types.h>

#include <string>
#include <vector>

namespace tcs {

// 0 if it is gone.
pid_t proc_parent(pid_t pid);
// Its comm (the program it runs), or fallback.
std::string proc_name(pid_t pid, const std::string &fallback);
// A zombie's wait status (stat field 52, exit_code); 0 if it is gone.
int proc_exit_status(pid_t pid);
// Whether every thread of it is asleep in the kernel (state S or D), or it
// is gone; a running or stopped thread counts as awake.
bool proc_all_threads_asleep(pid_t pid);

// How many live threads pid has: read at each wait of a multi-threaded
// controller.
int proc_thread_count(pid_t pid);
// Each live thread of pid with its state letter (Z and X left out).
struct ThreadState {
	pid_t tid;
	char state;
};
std::vector<ThreadState> proc_thread_states(pid_t pid);
// Whether every thread of pid is stopped (state T or t), or it is gone.
bool proc_all_threads_stopped(pid_t pid);
// Whether tid is a thread of pid.
bool proc_has_thread(pid_t pid, pid_t tid);
// Whether a task (process or thread) tid exists anywhere.
bool proc_task_exists(pid_t tid);
// Whether pid has a library whose file name contains name mapped (true too
// if its maps cannot be read or are empty: no verdict).
bool proc_maps_library(pid_t pid, const char *name);
// Whether pid, a program just started by exec, will load a library whose
// file name contains name: mapped already, or a dynamic program (its loader
// is mapped) with LD_PRELOAD naming it. Unknown while its exec is still
// setting up the new image (a vfork parent resumes before it is done):
// until its environment can be read.
enum class WillLoad { Yes, No, Unknown };
WillLoad proc_will_load(pid_t pid, const char *name);
// Whether signal sig sent to pid now would end it by its default action
// (as SIGTERM ends a program that set nothing for it): pid neither catches
// nor ignores it, and some live thread does not block it. False if it is
// gone or cannot be read.
bool proc_signal_kills(pid_t pid, int sig);
// The children of pid (of all its threads), from /proc.
std::vector<pid_t> proc_children(pid_t pid);

} // namespace tcs
