// read_xml_facts: one walk over the document's elements; line_named: the
// names libsdformat's and urdfdom's messages quote.
#include "xml_facts.h"

#include <cmath>
#include <cstdlib>
#include <vector>

#include "robot_xml.h"

namespace tcs::sim::robot {

namespace {

using tinyxml2::XMLElement;

Status check_sdf_mass(const std::string &file, const XMLElement *mass)
{
	const char *text = mass->GetText();
	std::string v = text ? text : "";
	char *end = nullptr;
	double d = std::strtod(v.c_str(), &end);
	while (end && (*end == ' ' || *end == '\t' || *end == '\n' || *end == '\r'))
		end++;
	if (v.empty() || end == v.c_str() || *end != '\0')
		return at(file, mass->GetLineNum(), "<mass>" + v + "</mass>: not a number");
	if (!std::isfinite(d))
		return at(file, mass->GetLineNum(), "<mass>" + v + "</mass>: not a finite number");
	if (d < 0)
		return at(file, mass->GetLineNum(), "<mass>" + v + "</mass>: a negative mass");
	return Ok{};
}

int lookup(const XmlFacts &f, const std::string &name)
{
	for (const auto *lines : { &f.link_line, &f.joint_line })
		if (auto it = lines->find(name); it != lines->end())
			return it->second;
	return 0;
}

} // namespace

Result<XmlFacts> read_xml_facts(const std::string &file, const tinyxml2::XMLDocument &doc)
{
	XmlFacts f;
	bool sdf = doc.RootElement() && std::string(doc.RootElement()->Name()) == "sdf";
	// Iterative: the depth is tinyxml2's to bound, not this stack's.
	std::vector<const XMLElement *> todo{ doc.RootElement() };
	while (!todo.empty()) {
		const XMLElement *e = todo.back();
		todo.pop_back();
		if (!e)
			continue;
		std::string tag = e->Name();
		const char *name = e->Attribute("name");
		if (tag == "link" && name) {
			f.link_line[name] = e->GetLineNum();
			if (++f.links > max_links)
				return at(file, e->GetLineNum(), "more than " + std::to_string(max_links) +
									 " links: tcs loads at most " + std::to_string(max_links) +
									 " (libsdformat needs about 1.5 MB and 10 ms for each)");
		} else if (tag == "joint" && name) {
			f.joint_line[name] = e->GetLineNum();
		} else if (sdf && tag == "mass" && e->Parent() && e->Parent()->ToElement() &&
			   std::string(e->Parent()->ToElement()->Name()) == "inertial") {
			auto st = check_sdf_mass(file, e);
			if (!st.ok())
				return st.error();
		}
		// Children pushed last first, so that they are seen in file order.
		std::vector<const XMLElement *> kids;
		for (const XMLElement *c = e->FirstChildElement(); c; c = c->NextSiblingElement())
			kids.push_back(c);
		todo.insert(todo.end(), kids.rbegin(), kids.rend());
	}
	return f;
}

int line_named(const XmlFacts &f, const std::string &message)
{
	// "[x]": libsdformat's way of quoting a name.
	for (size_t open = message.find('['); open != std::string::npos; open = message.find('[', open + 1)) {
		size_t close = message.find(']', open);
		if (close == std::string::npos)
			break;
		if (int line = lookup(f, message.substr(open + 1, close - open - 1)))
			return line;
	}
	// "named x": its other way.
	const std::string named = "named ";
	for (size_t at_ = message.find(named); at_ != std::string::npos; at_ = message.find(named, at_ + 1)) {
		size_t b = at_ + named.size(), e = message.find_first_of(" \t\n", b);
		std::string name = message.substr(b, e == std::string::npos ? std::string::npos : e - b);
		while (!name.empty() && (name.back() == '.' || name.back() == ',' || name.back() == ':'))
			name.pop_back();
		if (int line = lookup(f, name))
			return line;
	}
	return 0;
}

} // namespace tcs::sim::robot
