// A controller's states and the moves between them, as a pure table
// (docs/ARCHITECTURE.md, "A controller's states"; unit-tested in
// tests/unit/test_controller_state.cc). The one writer of a controller's
// state is transitions.cc, which carries a move out only where this table
// allows it.
#pragma once

#include <cstdint>
#include <optional>

namespace tcs {

enum class CtlState : uint8_t {
	Ready,   // may run: held by SIGSTOP, or woken and not yet resumed
	Running, // resumed in a lane; it runs until it waits or its budget ends
	Blocked, // in a request of ours that the scheduler ends (a wait, a read)
	Asleep,  // asleep in the kernel outside our hooks: looked at each step
	Dropped, // killed for what it sent: its end is all that is awaited
	Exited,
};

enum class CtlMove : uint8_t {
	Resume,   // its turn: Ready -> Running
	Block,    // it waits in a request of ours (or all its threads do)
	Preempt,  // its budget ended (SIGSTOP), or a replayed spin's stop
	Ahead,    // a device request ahead of the world: it waits for its step
	Wake,     // what it waits in is answered (or due): Blocked -> Ready
	SetAside, // it waits on, but another of its threads runs now
	StepAside, // found asleep outside our hooks
	Awake,    // an asleep one woke (or asked something)
	End,      // the run ends: it runs to act on SIGTERM, its waits answered
	Drop,
	Exit,
};

// The state `move` takes a controller in `from` to; none if the move is
// not one it can make there (a defect of ours: transitions.cc says so).
constexpr std::optional<CtlState> after(CtlState from, CtlMove move)
{
	using S = CtlState;
	using M = CtlMove;
	switch (move) {
	case M::Resume:
		return from == S::Ready ? std::optional(S::Running) : std::nullopt;
	case M::Block:
		// (Ready: stopped just as it began to wait, or a new child
		// waiting for its first answer.)
		return from == S::Running || from == S::Ready ? std::optional(S::Blocked) : std::nullopt;
	case M::Preempt:
		return from == S::Running ? std::optional(S::Ready) : std::nullopt;
	case M::Ahead:
		return from == S::Running || from == S::Ready ? std::optional(S::Ready) : std::nullopt;
	case M::Wake:
		// (Ready: a device read ahead of the world, ended by a handler.)
		return from == S::Blocked || from == S::Ready ? std::optional(S::Ready) : std::nullopt;
	case M::SetAside:
		return from == S::Blocked ? std::optional(S::Ready) : std::nullopt;
	case M::StepAside:
		return from == S::Running ? std::optional(S::Asleep) : std::nullopt;
	case M::Awake:
		return from == S::Asleep ? std::optional(S::Ready) : std::nullopt;
	case M::End:
		return from == S::Dropped || from == S::Exited ? std::nullopt : std::optional(S::Running);
	case M::Drop:
		return from == S::Exited ? std::nullopt : std::optional(S::Dropped);
	case M::Exit:
		return from == S::Exited ? std::nullopt : std::optional(S::Exited);
	}
	return std::nullopt;
}

// Waiting on something of the world's or another controller's: a signal
// sent to it is looked at where the world is.
constexpr bool waiting(CtlState s)
{
	return s == CtlState::Blocked || s == CtlState::Asleep;
}

const char *state_name(CtlState s);
const char *move_name(CtlMove m);

} // namespace tcs
