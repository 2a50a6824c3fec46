// read_robot_xml: the file's bytes, tinyxml2's parse of them, and which of
// the two formats its root element says it is.
#include "robot_xml.h"

#include "read_file.h"

namespace tcs::sim::robot {

namespace {

// Robot files are a few hundred kilobytes at most; a mesh-heavy one is
// still far below this.
constexpr size_t max_file_bytes = 64u << 20;

// tinyxml2's own names for its errors (XML_ERROR_MISMATCHED_ELEMENT) are
// not for users.
const char *syntax_cause(tinyxml2::XMLError e)
{
	switch (e) {
	case tinyxml2::XML_ERROR_PARSING_ELEMENT:
		return "an element is not closed or is malformed";
	case tinyxml2::XML_ERROR_PARSING_ATTRIBUTE:
		return "a malformed attribute";
	case tinyxml2::XML_ERROR_PARSING_TEXT:
		return "malformed text";
	case tinyxml2::XML_ERROR_PARSING_CDATA:
		return "a malformed CDATA section";
	case tinyxml2::XML_ERROR_PARSING_COMMENT:
		return "a comment is not closed";
	case tinyxml2::XML_ERROR_PARSING_DECLARATION:
		return "a malformed <?...?> declaration";
	case tinyxml2::XML_ERROR_PARSING_UNKNOWN:
		return "a malformed <!...> construct";
	case tinyxml2::XML_ERROR_EMPTY_DOCUMENT:
		return "the file is empty";
	case tinyxml2::XML_ERROR_MISMATCHED_ELEMENT:
		return "a closing tag does not match its opening tag";
	case tinyxml2::XML_ELEMENT_DEPTH_EXCEEDED:
		return "elements are nested too deeply";
	default:
		return "the file is not well-formed XML";
	}
}

} // namespace

Error at(const std::string &file, int line, const std::string &message)
{
	if (line > 0)
		return Error{ file + ":" + std::to_string(line) + ": " + message };
	return Error{ file + ": " + message };
}

std::string one_line(std::string s)
{
	size_t b = s.find_first_not_of(" \t\n");
	s.erase(0, b == std::string::npos ? s.size() : b);
	for (char &c : s)
		if (c == '\n' || c == '\t')
			c = ' ';
	while (!s.empty() && s.back() == ' ')
		s.pop_back();
	return s;
}

Result<RobotXml> read_robot_xml(const std::string &path)
{
	auto bytes = read_file(path, max_file_bytes);
	if (!bytes.ok())
		return bytes.error();
	RobotXml x;
	x.text = std::move(*bytes);
	x.doc = std::make_unique<tinyxml2::XMLDocument>();
	// Parse(p, len) stops at len: a NUL inside the file is an error, not
	// the end of it.
	tinyxml2::XMLError e = x.doc->Parse(x.text.data(), x.text.size());
	if (e != tinyxml2::XML_SUCCESS) {
		return at(path, x.doc->ErrorLineNum(), std::string("XML syntax error: ") + syntax_cause(e));
	}
	const tinyxml2::XMLElement *root = x.doc->RootElement();
	if (!root)
		return at(path, 0, "XML syntax error: the file has no element");
	std::string name = root->Name();
	if (name == "robot")
		x.format = RobotFormat::urdf;
	else if (name == "sdf")
		x.format = RobotFormat::sdf;
	else
		return at(path, root->GetLineNum(),
			  "neither URDF (<robot>) nor SDF (<sdf>): the root element is <" + name + ">");
	return x;
}

} // namespace tcs::sim::robot
