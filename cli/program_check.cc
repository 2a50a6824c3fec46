// resolve_program() and check_preloadable(): ELF and #! inspection.
#include "program_check.h"

#include <elf.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <vector>

#include "unique_fd.h"

namespace tcs {

namespace {

#if defined(__x86_64__)
constexpr int kMachine = EM_X86_64;
#elif defined(__aarch64__)
constexpr int kMachine = EM_AARCH64;
#else
constexpr int kMachine = -1; // unknown: do not check
#endif

bool read_at(int fd, void *buf, size_t len, off_t off)
{
	return pread(fd, buf, len, off) == (ssize_t)len;
}

Status check_elf(const std::string &path, int fd)
{
	Elf64_Ehdr eh;
	if (!read_at(fd, &eh, sizeof eh, 0) || memcmp(eh.e_ident, ELFMAG, SELFMAG) != 0)
		return Error{ path + ": not an executable this system can run" };
	if (eh.e_ident[EI_CLASS] != ELFCLASS64)
		return Error{ path + " is a 32-bit program; libtcs_preload is 64-bit and could not hook it" };
	if (kMachine >= 0 && eh.e_machine != kMachine)
		return Error{ path + " is built for another architecture" };
	bool interp = false;
	for (int i = 0; i < eh.e_phnum && i < 4096; i++) {
		Elf64_Phdr ph;
		if (!read_at(fd, &ph, sizeof ph, (off_t)(eh.e_phoff + (uint64_t)i * eh.e_phentsize)))
			return Error{ path + ": truncated ELF file" };
		interp |= ph.p_type == PT_INTERP;
	}
	if (!interp)
		return Error{ path +
			      " is statically linked: LD_PRELOAD cannot hook it, so it would run in real time. "
			      "Link it dynamically to run it under tcs." };
	return Ok{};
}

// The interpreter of a #! script, resolved ("/usr/bin/env python3" → python3's path).
Result<std::string> script_interpreter(const std::string &path, int fd)
{
	char line[256] = {};
	ssize_t n = pread(fd, line, sizeof line - 1, 0);
	if (n < 2 || line[0] != '#' || line[1] != '!')
		return Error{ path + ": not an executable this system can run (neither ELF nor a #! script)" };
	line[n] = '\0';
	std::vector<std::string> words;
	std::string word;
	for (char *p = line + 2; *p && *p != '\n'; p++) {
		if (*p == ' ' || *p == '\t') {
			if (!word.empty())
				words.push_back(word);
			word.clear();
		} else {
			word += *p;
		}
	}
	if (!word.empty())
		words.push_back(word);
	if (words.empty())
		return Error{ path + ": empty #! line" };
	if (words[0].size() >= 4 && words[0].compare(words[0].size() - 4, 4, "/env") == 0) {
		size_t i = 1;
		while (i < words.size() && words[i][0] == '-')
			i++;
		if (i == words.size())
			return Error{ path + ": #!" + words[0] + " names no program" };
		return resolve_program(words[i]);
	}
	return words[0];
}

} // namespace

Result<std::string> resolve_program(const std::string &name)
{
	if (name.empty())
		return Error{ "empty program name" };
	auto usable = [](const std::string &p, std::string *why) {
		struct stat st;
		if (stat(p.c_str(), &st) < 0) {
			*why = std::strerror(errno);
			return false;
		}
		if (S_ISDIR(st.st_mode)) {
			*why = "is a directory";
			return false;
		}
		if (access(p.c_str(), X_OK) < 0) {
			*why = "not executable";
			return false;
		}
		return true;
	};
	std::string why;
	if (name.find('/') != std::string::npos) {
		if (usable(name, &why))
			return name;
		return Error{ name + ": " + why };
	}
	const char *path = getenv("PATH");
	std::string dirs = path ? path : "/usr/local/bin:/usr/bin:/bin";
	size_t start = 0;
	for (;;) {
		size_t end = dirs.find(':', start);
		std::string dir = dirs.substr(start, end == std::string::npos ? std::string::npos : end - start);
		std::string cand = (dir.empty() ? "." : dir) + "/" + name;
		if (usable(cand, &why))
			return cand;
		if (end == std::string::npos)
			break;
		start = end + 1;
	}
	return Error{ name + ": command not found" };
}

Status check_preloadable(const std::string &path)
{
	std::string current = path;
	for (int depth = 0; depth < 5; depth++) {
		UniqueFd fd(open(current.c_str(), O_RDONLY | O_CLOEXEC));
		if (!fd)
			return errno_error("cannot open " + current);
		struct stat st;
		if (fstat(fd.get(), &st) == 0 && (((st.st_mode & S_ISUID) && st.st_uid != geteuid()) ||
						  ((st.st_mode & S_ISGID) && st.st_gid != getegid())))
			return Error{ current + " is set-user-ID or set-group-ID: the loader ignores LD_PRELOAD for it" };
		char magic[4] = {};
		(void)!pread(fd.get(), magic, sizeof magic, 0);
		if (memcmp(magic, ELFMAG, SELFMAG) == 0)
			return check_elf(current, fd.get());
		auto interp = script_interpreter(current, fd.get());
		if (!interp)
			return interp.error();
		current = *interp;
	}
	return Error{ path + ": too many nested #! interpreters" };
}

} // namespace tcs
