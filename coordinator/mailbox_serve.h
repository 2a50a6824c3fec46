// The coordinator's side of one controller's mailbox (tcs/mailbox.h): what
// it takes out of shared memory it copies first and checks as it would a
// message from the channel; every answer to a request taken here goes
// through answer(), which says whether the channel must carry it too.
#pragma once

#include "tcs/mailbox.h"

namespace tcs {

class Mailbox {
public:
	// The page's mailbox, or nullptr once the page is gone.
	void attach(tcs_mailbox *box)
	{
		box_ = box;
		pending_ = false;
	}
	// A posted request, copied into buf (sizeof(tcs_msg) bytes, unchecked)
	// and its bit cleared; false if there is none.
	bool take(unsigned char *buf);
	// The pending request will not be answered at once: the controller
	// stops spinning and waits on its channel.
	void park();
	// Answers the pending request: true if the mailbox delivered it, false
	// if it must go on the channel (parked, or nothing pending).
	bool answer(const tcs_msg &m);
	// A request posted and not yet taken, or taken and not yet answered:
	// the controller waits for the coordinator.
	bool requested() const;
	// The coordinator's promise to look without being rung. Taken back with
	// a full barrier: a request posted before is seen by the next take().
	void set_polling(bool on);

private:
	tcs_mailbox *box_ = nullptr;
	bool pending_ = false;
};

} // namespace tcs
