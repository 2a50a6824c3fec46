// The names of a controller's states and moves (controller_state.h).
#include "controller_state.h"

namespace tcs {

const char *state_name(CtlState s)
{
	switch (s) {
	case CtlState::Ready: return "ready";
	case CtlState::Running: return "running";
	case CtlState::Blocked: return "blocked";
	case CtlState::Asleep: return "asleep";
	case CtlState::Dropped: return "dropped";
	case CtlState::Exited: return "exited";
	}
	return "?";
}

const char *move_name(CtlMove m)
{
	switch (m) {
	case CtlMove::Resume: return "resume";
	case CtlMove::Block: return "block";
	case CtlMove::Preempt: return "preempt";
	case CtlMove::Ahead: return "ahead";
	case CtlMove::Wake: return "wake";
	case CtlMove::SetAside: return "set aside";
	case CtlMove::StepAside: return "step aside";
	case CtlMove::Awake: return "awake";
	case CtlMove::End: return "end";
	case CtlMove::Drop: return "drop";
	case CtlMove::Exit: return "exit";
	}
	return "?";
}

} // namespace tcs
