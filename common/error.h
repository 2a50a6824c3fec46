// Errors as values: every fallible function of tcs's C++ returns a
// Result<T> carrying either its value or an Error whose message names the
// cause. Only the front ends turn an Error into output and an exit status
// (and simhost's ode_plugin.cc into the C ABI's err buffer).
#pragma once

#include <cerrno>
#include <cstring>
#include <string>
#include <utility>
#include <variant>

namespace tcs {

struct Error {
	std::string message;
};

// "what: strerror(err)".
inline Error errno_error(const std::string &what, int err = errno)
{
	return Error{ what + ": " + std::strerror(err) };
}

template <class T> class [[nodiscard]] Result {
public:
	Result(T value) : v_(std::move(value)) {}
	Result(Error e) : v_(std::move(e)) {}
	bool ok() const { return v_.index() == 0; }
	explicit operator bool() const { return ok(); }
	T &value() { return std::get<0>(v_); }
	T &operator*() { return value(); }
	T *operator->() { return &value(); }
	const Error &error() const { return std::get<1>(v_); }

private:
	std::variant<T, Error> v_;
};

struct Ok {};
using Status = Result<Ok>;

} // namespace tcs
