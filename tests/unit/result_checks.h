// cmocka checks for tcs::Result and tcs::Status: a failure prints the
// expression and the error's message. Include after <cmocka.h>.
#pragma once

#include <utility>

#include "error.h"

#define CHECK_OK(expr)                                                                          \
	do {                                                                                    \
		auto r_ = (expr);                                                               \
		if (!r_.ok()) {                                                                 \
			print_error("%s failed: %s\n", #expr, r_.error().message.c_str());      \
			fail();                                                                 \
		}                                                                               \
	} while (0)

template <class T> T must(tcs::Result<T> r, const char *what)
{
	if (!r.ok()) {
		print_error("%s failed: %s\n", what, r.error().message.c_str());
		fail();
	}
	return std::move(*r);
}
// The value of a Result that must be one.
#define MUST(expr) must((expr), #expr)
