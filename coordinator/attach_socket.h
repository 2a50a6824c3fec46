// coordinatord's Unix socket, as both ends open it: where it lives by
// default, creating it 0600 for its owner alone, connecting with errors
// that say what to do, the peer's uid (SO_PEERCRED), and sending and
// receiving frames with the descriptors that ride along.
#pragma once

#include <sys/types.h>

#include <string>
#include <string_view>
#include <vector>

#include "error.h"
#include "unique_fd.h"

namespace tcs {

// $XDG_RUNTIME_DIR/tcs/coordinatord.sock, or /run/tcs/coordinatord.sock
// as root.
Result<std::string> default_socket_path();
// Binds and listens (non-blocking). A socket file nobody answers on is
// stale and replaced; one a live daemon answers on is an error.
Result<UniqueFd> listen_socket(const std::string &path);
Result<UniqueFd> connect_socket(const std::string &path);
Result<uid_t> peer_uid(int fd);

// Sends a whole frame (blocking socket), fds with its first bytes.
Status send_frame(int fd, std::string_view frame, const std::vector<int> &fds = {});
// One non-blocking read appended to buf, with any fds that came (at most
// max_fds are kept; more are closed). 0 at end of stream, -1 with errno.
ssize_t recv_some(int fd, std::string &buf, std::vector<UniqueFd> &fds, size_t max_fds);

} // namespace tcs
