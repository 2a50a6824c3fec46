// Mailbox: the coordinator's half of the hand-off in tcs/mailbox.h.
#include "mailbox_serve.h"

#include <cstring>

namespace tcs {

bool Mailbox::take(unsigned char *buf)
{
	if (!box_ || !(__atomic_load_n(&box_->state, __ATOMIC_ACQUIRE) & TCS_MBOX_REQUEST))
		return false;
	// Copied before anything looks at it: the controller may write it
	// again meanwhile, and only the copy is checked.
	std::memcpy(buf, &box_->request, sizeof box_->request);
	__atomic_fetch_and(&box_->state, ~TCS_MBOX_REQUEST, __ATOMIC_ACQ_REL);
	pending_ = true;
	return true;
}

bool Mailbox::requested() const
{
	return pending_ || (box_ && (__atomic_load_n(&box_->state, __ATOMIC_ACQUIRE) & TCS_MBOX_REQUEST));
}

void Mailbox::park()
{
	if (box_ && pending_)
		__atomic_fetch_or(&box_->state, TCS_MBOX_PARK, __ATOMIC_ACQ_REL);
}

bool Mailbox::answer(const tcs_msg &m)
{
	if (!box_ || !pending_)
		return false;
	pending_ = false;
	std::memcpy(&box_->answer, &m, sizeof m);
	uint32_t old = __atomic_fetch_or(&box_->state, TCS_MBOX_ANSWER, __ATOMIC_ACQ_REL);
	return !(old & TCS_MBOX_PARK);
}

void Mailbox::set_polling(bool on)
{
	if (box_)
		__atomic_store_n(&box_->polling, on ? 1u : 0u, __ATOMIC_SEQ_CST);
}

} // namespace tcs
