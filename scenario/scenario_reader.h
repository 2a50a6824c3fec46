// What the scenario parser's sections are read with: toml++ configured as
// the parser needs it, a table's entries in file order, and the scenario
// being read, whose errors are "FILE:LINE: what is wrong". Internal to
// scenario/ (scenario.cc and the sections' parsers).
#pragma once

// toml++ reports errors as values only when built without exceptions; it
// is used header-only for that reason (Debian's shared build throws), and
// only in scenario/'s parser, which includes it here alone so that every
// file of it sees the same configuration. Its assertions are
// preconditions that 3.3 breaks on malformed input ("[=x]", "[1, }":
// upstream PR 301) where the code after them reports the error properly:
// off, as in any GCC release build.
#define TOML_EXCEPTIONS 0
#define TOML_ASSERT(expr) static_assert(true)
#include <toml++/toml.h>

#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "error.h"
#include "scenario.h"

namespace tcs::scenario_parse {

int line_of(const toml::node &n);
// "a table", "an integer", ...: for messages.
const char *type_name(const toml::node &n);
std::string join(const std::vector<std::string> &v);
// "0x068": a CAN id or an I2C address as the data sheets write them, at
// least `digits` hex digits.
std::string hex(uint64_t v, int digits);

struct Entry {
	int line;
	std::string key;
	const toml::node *node;
};

// A table's entries in file order (toml++ keeps them sorted by key).
std::vector<Entry> entries(const toml::table &t);
// One key of t, if there.
std::optional<Entry> lookup(const toml::table &t, std::string_view key);
// The key's entry, or nullptr.
const Entry *find_entry(const std::vector<Entry> &es, std::string_view key);

// The scenario read so far, and how its values are read: each error is
// "FILE:LINE: what is wrong".
class ScenarioReader {
public:
	ScenarioReader(std::string file, std::string folder);

	Scenario sc;
	std::string dir;                    // the file's folder, for relative model paths
	std::optional<ModelSpec> sim_model; // [sim] model, before the models are known

	Error err(int line, const std::string &what) const;
	// An unknown key of t (the first in file order) is an error.
	Status check_keys(const toml::table &t, const std::string &where,
			  std::initializer_list<const char *> known) const;
	Result<std::string> get_string(const Entry &e, const std::string &example) const;
	Result<double> get_number(const Entry &e, const std::string &what) const;
	// A TOML integer (not a float, even 1.0: ids and rates are counted).
	Result<int64_t> get_integer(const Entry &e, const std::string &example) const;
	Result<bool> get_bool(const Entry &e) const;
	// A signal name of one of the models read so far, in its parts.
	Result<SignalParts> signal_parts(int line, const std::string &name) const;
	// A joint's or a link's name, "<model>.<part>", of one of the models
	// read so far (`key` is "joint" or "link", for messages); the parts
	// view `name`, and the field is empty.
	Result<SignalParts> part_name(int line, const std::string &key, const std::string &name) const;
	// An array of tables under `key`, written [[key]] (or [[written]], for a
	// table's own: "can.motor"); empty if absent.
	Result<std::vector<const toml::table *>> table_array(const toml::table &root, const char *key,
							     const char *written = nullptr) const;

private:
	// The model a name (`what`, for messages) starts with is one read so far.
	Status model_known(int line, const std::string &what, std::string_view model) const;
};

} // namespace tcs::scenario_parse
