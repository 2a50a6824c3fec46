// notify_systemd(): the sd_notify(3) datagram.
#include "sd_notify.h"

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstddef>
#include <cstdlib>
#include <cstring>

#include "unique_fd.h"

namespace tcs {

void notify_systemd(const std::string &state)
{
	const char *path = getenv("NOTIFY_SOCKET");
	if (!path || (path[0] != '/' && path[0] != '@'))
		return;
	sockaddr_un a = {};
	a.sun_family = AF_UNIX;
	size_t len = strlen(path);
	if (len >= sizeof a.sun_path)
		return;
	memcpy(a.sun_path, path, len);
	if (a.sun_path[0] == '@')
		a.sun_path[0] = '\0'; // an abstract socket
	UniqueFd fd(socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0));
	if (!fd)
		return;
	(void)sendto(fd.get(), state.data(), state.size(), MSG_NOSIGNAL, (const sockaddr *)&a,
		     (socklen_t)(offsetof(sockaddr_un, sun_path) + len));
}

} // namespace tcs
