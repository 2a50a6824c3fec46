// read_file: open, read to the end (a pipe or /dev/stdin too), close.
#include "read_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "unique_fd.h"

namespace tcs {

Result<std::string> read_file(const std::string &path, size_t limit)
{
	UniqueFd fd(open(path.c_str(), O_RDONLY | O_CLOEXEC));
	if (fd.get() < 0)
		return errno_error(path);
	struct stat st;
	if (fstat(fd.get(), &st) < 0)
		return errno_error(path);
	if (S_ISDIR(st.st_mode))
		return errno_error(path, EISDIR);
	std::string bytes;
	if (S_ISREG(st.st_mode) && (size_t)st.st_size <= limit)
		bytes.reserve((size_t)st.st_size);
	char buf[65536];
	for (;;) {
		ssize_t n = read(fd.get(), buf, sizeof buf);
		if (n < 0 && errno == EINTR)
			continue;
		if (n < 0)
			return errno_error(path);
		if (n == 0)
			return bytes;
		bytes.append(buf, (size_t)n);
		if (bytes.size() > limit)
			return Error{ path + ": larger than " + std::to_string(limit) + " bytes" };
	}
}

} // namespace tcs
