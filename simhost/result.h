// Errors as values inside the simulation host: a fallible function returns
// a Result<T> holding its value or an Error whose one-line message names
// the cause. Only ode_plugin.cc turns an Error into the C ABI's err buffer.
// (The coordinator has its own; simhost depends on nothing above it.)
#pragma once

#include <string>
#include <utility>
#include <variant>

namespace tcs::sim {

struct Error {
	std::string message;
};

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

} // namespace tcs::sim
