// Unit tests for coordinatord's socket (coordinator/attach_socket.h), as
// both ends open it, in a temporary folder: its mode, a live daemon's
// socket kept, a stale one replaced, the errors a client sees, the peer's
// uid and descriptors that ride along with frames.
#include <fcntl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

extern "C" {
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>
}

#include "attach_checks.h"
#include "attach_protocol.h"
#include "attach_socket.h"
#include "result_checks.h"

using namespace tcs;

namespace {

using namespace attach_checks;

// ---- The socket ----

struct TempDir {
	TempDir()
	{
		char tmpl[] = "/tmp/tcs-attach-XXXXXX";
		assert_non_null(mkdtemp(tmpl));
		path = tmpl;
	}
	~TempDir() { (void)!system(("rm -rf '" + path + "'").c_str()); }
	std::string path;
};

mode_t mode_of(const std::string &path)
{
	struct stat st;
	if (lstat(path.c_str(), &st) < 0)
		return 0;
	return st.st_mode;
}

void socket_listen_connect(void **)
{
	TempDir tmp;
	// The folder is made for its owner alone, the socket 0600.
	const std::string dir = tmp.path + "/tcs";
	const std::string path = dir + "/coordinatord.sock";
	UniqueFd listening = MUST(listen_socket(path));
	assert_true(S_ISDIR(mode_of(dir)));
	assert_int_equal(mode_of(dir) & 07777, 0700);
	assert_true(S_ISSOCK(mode_of(path)));
	assert_int_equal(mode_of(path) & 07777, 0600);
	assert_true(fcntl(listening.get(), F_GETFL) & O_NONBLOCK);
	assert_true(fcntl(listening.get(), F_GETFD) & FD_CLOEXEC);

	UniqueFd client = MUST(connect_socket(path));
	UniqueFd served(accept4(listening.get(), nullptr, nullptr, SOCK_CLOEXEC));
	assert_true(served.get() >= 0);
	assert_int_equal(MUST(peer_uid(served.get())), geteuid());
	assert_int_equal(MUST(peer_uid(client.get())), geteuid());
	assert_false(peer_uid(-1).ok());

	// A live daemon's socket is kept.
	auto second = listen_socket(path);
	assert_false(second.ok());
	assert_true(contains(second.error().message, "another coordinatord is serving there"));
	assert_true(contains(second.error().message, path.c_str()));
	assert_true(S_ISSOCK(mode_of(path)));
	UniqueFd again = MUST(connect_socket(path)); // and still answers
	again.reset();

	// Its daemon gone, the socket file stays: stale, and replaced.
	listening.reset();
	served.reset();
	client.reset();
	assert_true(S_ISSOCK(mode_of(path)));
	auto stale = connect_socket(path);
	assert_false(stale.ok());
	assert_true(contains(stale.error().message, "no coordinatord answers there"));
	listening = MUST(listen_socket(path));
	assert_int_equal(mode_of(path) & 07777, 0600);
	client = MUST(connect_socket(path));
	unlink(path.c_str());
}

void socket_errors(void **)
{
	TempDir tmp;
	auto missing = connect_socket(tmp.path + "/nobody.sock");
	assert_false(missing.ok());
	assert_true(contains(missing.error().message, "no coordinatord there"));
	assert_true(contains(missing.error().message, "nobody.sock"));

	// Longer than sun_path holds: refused by both ends, saying the limit.
	const size_t limit = sizeof(sockaddr_un{}.sun_path) - 1;
	const std::string longest = tmp.path + "/" + std::string(limit - tmp.path.size() - 1, 's');
	assert_int_equal(longest.size(), limit);
	MUST(listen_socket(longest)).reset();
	unlink(longest.c_str());
	const std::string too_long = longest + "s";
	const std::string expected = "a socket path must be 1 to " + std::to_string(limit) + " bytes long";
	auto l = listen_socket(too_long);
	assert_false(l.ok());
	assert_true(contains(l.error().message, expected.c_str()));
	auto c = connect_socket(too_long);
	assert_false(c.ok());
	assert_true(contains(c.error().message, expected.c_str()));
	assert_false(listen_socket("").ok());

	// Something else at the path is left alone.
	const std::string file = tmp.path + "/file";
	UniqueFd f(open(file.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0600));
	assert_true(f.get() >= 0);
	auto on_file = listen_socket(file);
	assert_false(on_file.ok());
	assert_true(contains(on_file.error().message, "exists and is not a socket"));
	assert_true(S_ISREG(mode_of(file)));
}

// A frame with stdin, stdout and stderr riding along, as tcs-run sends its
// RUN; the receiver keeps no more descriptors than it asks for.
void socket_frames_with_fds(void **)
{
	int sv[2];
	assert_int_equal(socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv), 0);
	UniqueFd a(sv[0]), b(sv[1]);
	const std::string frame = encode_frame(AttachType::Run, encode_run(typical_run()));
	CHECK_OK(send_frame(a.get(), frame, { 0, 1, 2 }));
	CHECK_OK(send_frame(a.get(), encode_frame(AttachType::Signal, encode_signal(2)), { 0, 1, 2 }));

	std::string in;
	std::vector<UniqueFd> fds;
	while (in.size() < frame.size())
		assert_true(recv_some(b.get(), in, fds, 3) > 0);
	assert_int_equal(fds.size(), 3);
	for (auto &fd : fds)
		assert_true(fcntl(fd.get(), F_GETFD) & FD_CLOEXEC);
	auto f = MUST(take_frame(in));
	assert_true(f && f->type == AttachType::Run);

	// The second frame's descriptors are closed, not kept.
	std::vector<UniqueFd> more;
	while (in.size() < kAttachHeader + 4)
		assert_true(recv_some(b.get(), in, more, 0) > 0);
	assert_true(more.empty());
	f = MUST(take_frame(in));
	assert_true(f && f->type == AttachType::Signal);

	// Nothing more: EAGAIN, then the end of the stream.
	assert_int_equal(recv_some(b.get(), in, more, 0), -1);
	assert_int_equal(errno, EAGAIN);
	a.reset();
	assert_int_equal(recv_some(b.get(), in, more, 0), 0);
}

} // namespace

int main()
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(socket_listen_connect),
		cmocka_unit_test(socket_errors),
		cmocka_unit_test(socket_frames_with_fds),
	};
	return cmocka_run_group_tests(tests, nullptr, nullptr);
}
