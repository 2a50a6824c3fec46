// Readiness and status for systemd (Type=notify), without libsystemd: one
// datagram to $NOTIFY_SOCKET, as sd_notify(3) describes. Outside systemd,
// nothing.
#pragma once

#include <string>

namespace tcs {

void notify_systemd(const std::string &state);

} // namespace tcs
