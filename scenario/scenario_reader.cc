// Reading a scenario's TOML: entries in file order, typed values with the
// line they came from, errors as FILE:LINE (see scenario_reader.h).
#include "scenario_reader.h"

#include <algorithm>
#include <cmath>

#include "toml_text_shift.h"

namespace tcs::scenario_parse {

int line_of(const toml::node &n)
{
	return (int)n.source().begin.line;
}

const char *type_name(const toml::node &n)
{
	switch (n.type()) {
	case toml::node_type::table:
		return "a table";
	case toml::node_type::array:
		return "an array";
	case toml::node_type::string:
		return "a string";
	case toml::node_type::integer:
		return "an integer";
	case toml::node_type::floating_point:
		return "a float";
	case toml::node_type::boolean:
		return "a boolean";
	default:
		return "a date or time";
	}
}

std::string join(const std::vector<std::string> &v)
{
	std::string s;
	for (const auto &x : v)
		s += (s.empty() ? "" : ", ") + x;
	return s;
}

std::string hex(uint64_t v, int digits)
{
	static const char kDigits[] = "0123456789ABCDEF";
	std::string out;
	for (; v || (int)out.size() < digits; v >>= 4)
		out.insert(out.begin(), kDigits[v & 15]);
	return "0x" + out;
}

std::vector<Entry> entries(const toml::table &t)
{
	std::vector<Entry> v;
	for (auto &&[k, n] : t) {
		int line = (int)k.source().begin.line;
		v.push_back({ line ? line : line_of(n), unshift(k.str()), &n });
	}
	std::stable_sort(v.begin(), v.end(), [](const Entry &a, const Entry &b) { return a.line < b.line; });
	return v;
}

std::optional<Entry> lookup(const toml::table &t, std::string_view key)
{
	auto it = t.find(key);
	if (it == t.end())
		return std::nullopt;
	int line = (int)it->first.source().begin.line;
	return Entry{ line ? line : line_of(it->second), std::string(key), &it->second };
}

const Entry *find_entry(const std::vector<Entry> &es, std::string_view key)
{
	for (const Entry &e : es)
		if (e.key == key)
			return &e;
	return nullptr;
}

ScenarioReader::ScenarioReader(std::string file, std::string folder) : dir(std::move(folder))
{
	sc.file = std::move(file);
}

Error ScenarioReader::err(int line, const std::string &what) const
{
	return scenario_error(sc, line, what);
}

Status ScenarioReader::check_keys(const toml::table &t, const std::string &where,
				  std::initializer_list<const char *> known) const
{
	for (const Entry &e : entries(t)) {
		if (std::find(known.begin(), known.end(), e.key) != known.end())
			continue;
		std::string list;
		for (const char *k : known)
			list += (list.empty() ? "" : ", ") + std::string(k);
		return err(e.line, "unknown key '" + e.key + "' " + where + " (known: " + list + ")");
	}
	return Ok{};
}

Result<std::string> ScenarioReader::get_string(const Entry &e, const std::string &example) const
{
	if (!e.node->is_string())
		return err(e.line, e.key + " must be a string such as " + example + ", not " + type_name(*e.node));
	return unshift(e.node->as_string()->get());
}

Result<double> ScenarioReader::get_number(const Entry &e, const std::string &what) const
{
	std::optional<double> v;
	if (e.node->is_integer())
		v = (double)e.node->as_integer()->get();
	else if (e.node->is_floating_point())
		v = e.node->as_floating_point()->get();
	if (!v)
		return err(e.line, what + " must be a number, not " + type_name(*e.node));
	if (!std::isfinite(*v))
		return err(e.line, what + " must be a finite number");
	return *v;
}

Result<int64_t> ScenarioReader::get_integer(const Entry &e, const std::string &example) const
{
	if (!e.node->is_integer())
		return err(e.line, e.key + " must be an integer such as " + example + ", not " + type_name(*e.node));
	return e.node->as_integer()->get();
}

Result<bool> ScenarioReader::get_bool(const Entry &e) const
{
	if (!e.node->is_boolean())
		return err(e.line, e.key + " must be true or false, not " + std::string(type_name(*e.node)));
	return e.node->as_boolean()->get();
}

Result<std::vector<const toml::table *>> ScenarioReader::table_array(const toml::table &root, const char *key,
								     const char *written) const
{
	std::vector<const toml::table *> out;
	std::optional<Entry> e = lookup(root, key);
	if (!e)
		return out;
	const toml::array *a = e->node->as_array();
	if (!a || (!a->empty() && !a->is_array_of_tables()))
		return err(e->line, std::string("'") + key + "' must be written [[" + (written ? written : key) +
					    "]] (an array of tables)");
	for (const toml::node &n : *a)
		out.push_back(n.as_table());
	return out;
}

Result<SignalParts> ScenarioReader::signal_parts(int line, const std::string &name) const
{
	auto parts = split_signal_name(name);
	if (!parts)
		return err(line, "signal '" + name + "' is not <model>.<part>.<field> with field one of " +
					 signal_fields_text());
	if (Status s = model_known(line, "signal '" + name + "'", parts->model); !s)
		return s.error();
	return *parts;
}

Result<SignalParts> ScenarioReader::part_name(int line, const std::string &key, const std::string &name) const
{
	// A joint's or link's name is a signal's without the field: any field
	// completes it for the signal's syntax.
	auto whole = split_signal_name(name + ".pose");
	if (!whole)
		return err(line, key + " '" + name + "' is not <model>.<" + key + ">");
	std::string_view n = name;
	SignalParts parts{ n.substr(0, whole->model.size()), n.substr(whole->model.size() + 1), {} };
	if (Status s = model_known(line, key + " '" + name + "'", parts.model); !s)
		return s.error();
	return parts;
}

Status ScenarioReader::model_known(int line, const std::string &what, std::string_view model) const
{
	std::vector<std::string> models;
	for (const ModelSpec &m : sc.models) {
		if (m.name == model)
			return Ok{};
		models.push_back(m.name);
	}
	return err(line, what + ": the scenario has no model '" + std::string(model) + "' (models: " + join(models) +
				 ")");
}

} // namespace tcs::scenario_parse
