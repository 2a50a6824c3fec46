// coordinatord's socket: paths, permissions, peers, framed I/O.
#include "attach_socket.h"

#include <fcntl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>

namespace tcs {

namespace {

Result<sockaddr_un> address_of(const std::string &path)
{
	sockaddr_un a = {};
	a.sun_family = AF_UNIX;
	if (path.empty() || path.size() >= sizeof a.sun_path)
		return Error{ path + ": a socket path must be 1 to " + std::to_string(sizeof a.sun_path - 1) + " bytes long" };
	std::memcpy(a.sun_path, path.c_str(), path.size() + 1);
	return a;
}

} // namespace

Result<std::string> default_socket_path()
{
	std::string dir;
	if (geteuid() == 0)
		dir = "/run/tcs";
	else if (const char *xdg = getenv("XDG_RUNTIME_DIR"); xdg && *xdg == '/')
		dir = std::string(xdg) + "/tcs";
	else
		return Error{ "XDG_RUNTIME_DIR is not set: give the socket's path with --socket" };
	return dir + "/coordinatord.sock";
}

Result<UniqueFd> listen_socket(const std::string &path)
{
	auto addr = address_of(path);
	if (!addr)
		return addr.error();
	// The default folder is made for the daemon's user alone.
	size_t slash = path.find_last_of('/');
	std::string dir = slash == std::string::npos ? "" : path.substr(0, slash);
	if (!dir.empty() && mkdir(dir.c_str(), 0700) < 0 && errno != EEXIST)
		return errno_error("cannot create " + dir);
	UniqueFd fd(socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0));
	if (!fd)
		return errno_error("socket");
	struct stat st;
	if (lstat(path.c_str(), &st) == 0) {
		if (!S_ISSOCK(st.st_mode))
			return Error{ path + ": exists and is not a socket" };
		UniqueFd probe(socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
		if (!probe)
			return errno_error("socket");
		if (connect(probe.get(), (const sockaddr *)&*addr, sizeof *addr) == 0)
			return Error{ path + ": another coordinatord is serving there" };
		// Only a refusal says nobody listens; anything else (another
		// user's live daemon: EACCES) is not ours to remove.
		if (errno != ECONNREFUSED)
			return errno_error(path + ": cannot tell whether a coordinatord serves there");
		unlink(path.c_str()); // stale: its daemon is gone
	}
	// 0600 from the start: no moment where another user could connect.
	mode_t old = umask(0177);
	int rc = bind(fd.get(), (const sockaddr *)&*addr, sizeof *addr);
	int err = errno;
	umask(old);
	if (rc < 0)
		return errno_error("cannot bind " + path, err);
	if (chmod(path.c_str(), 0600) < 0 || listen(fd.get(), 64) < 0)
		return errno_error(path);
	return fd;
}

Result<UniqueFd> connect_socket(const std::string &path)
{
	auto addr = address_of(path);
	if (!addr)
		return addr.error();
	UniqueFd fd(socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
	if (!fd)
		return errno_error("socket");
	if (connect(fd.get(), (const sockaddr *)&*addr, sizeof *addr) == 0)
		return fd;
	switch (errno) {
	case ENOENT:
		return Error{ path + ": no coordinatord there (is it running? it prints its socket when it starts)" };
	case ECONNREFUSED:
		return Error{ path + ": no coordinatord answers there (a stale socket)" };
	case EACCES:
		return Error{ path + ": permission denied (coordinatord serves only its own user)" };
	default:
		return errno_error("cannot connect to " + path);
	}
}

Result<uid_t> peer_uid(int fd)
{
	struct ucred cred = {};
	socklen_t len = sizeof cred;
	if (getsockopt(fd, SOL_SOCKET, SO_PEERCRED, &cred, &len) < 0)
		return errno_error("SO_PEERCRED");
	return cred.uid;
}

Status send_frame(int fd, std::string_view frame, const std::vector<int> &fds)
{
	size_t sent = 0;
	while (sent < frame.size()) {
		struct iovec iov = { const_cast<char *>(frame.data() + sent), frame.size() - sent };
		struct msghdr mh = {};
		mh.msg_iov = &iov;
		mh.msg_iovlen = 1;
		std::vector<char> control;
		if (sent == 0 && !fds.empty()) {
			control.resize(CMSG_SPACE(sizeof(int) * fds.size()));
			mh.msg_control = control.data();
			mh.msg_controllen = control.size();
			struct cmsghdr *c = CMSG_FIRSTHDR(&mh);
			c->cmsg_level = SOL_SOCKET;
			c->cmsg_type = SCM_RIGHTS;
			c->cmsg_len = CMSG_LEN(sizeof(int) * fds.size());
			std::memcpy(CMSG_DATA(c), fds.data(), sizeof(int) * fds.size());
		}
		ssize_t n = sendmsg(fd, &mh, MSG_NOSIGNAL);
		if (n < 0 && errno == EINTR)
			continue;
		if (n < 0)
			return errno_error("send");
		sent += (size_t)n;
	}
	return Ok{};
}

ssize_t recv_some(int fd, std::string &buf, std::vector<UniqueFd> &fds, size_t max_fds)
{
	char data[16384];
	union {
		struct cmsghdr align;
		char buf[CMSG_SPACE(sizeof(int) * 8)];
	} control;
	struct iovec iov = { data, sizeof data };
	struct msghdr mh = {};
	mh.msg_iov = &iov;
	mh.msg_iovlen = 1;
	mh.msg_control = control.buf;
	mh.msg_controllen = sizeof control.buf;
	ssize_t n = recvmsg(fd, &mh, MSG_DONTWAIT | MSG_CMSG_CLOEXEC);
	if (n < 0)
		return n;
	for (struct cmsghdr *c = CMSG_FIRSTHDR(&mh); c; c = CMSG_NXTHDR(&mh, c)) {
		if (c->cmsg_level != SOL_SOCKET || c->cmsg_type != SCM_RIGHTS)
			continue;
		size_t count = (c->cmsg_len - CMSG_LEN(0)) / sizeof(int);
		for (size_t i = 0; i < count; i++) {
			int got;
			std::memcpy(&got, CMSG_DATA(c) + i * sizeof(int), sizeof got);
			UniqueFd owned(got);
			if (fds.size() < max_fds)
				fds.push_back(std::move(owned));
		}
	}
	buf.append(data, (size_t)n);
	return n;
}

} // namespace tcs
