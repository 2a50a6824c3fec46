// A robot file read as XML (tinyxml2), before libsdformat sees it: a file
// that is missing or not well-formed XML is refused here with the line
// tinyxml2 stopped at, which libsdformat would only report as "Unable to
// read file".
#pragma once

#include <memory>
#include <string>

#include <tinyxml2.h>

#include "error.h"

namespace tcs::sim::robot {

enum class RobotFormat { urdf, sdf };

struct RobotXml {
	std::string text; // the file's bytes
	std::unique_ptr<tinyxml2::XMLDocument> doc;
	RobotFormat format = RobotFormat::sdf;
};

// Reads and parses path. Errors: "PATH: strerror", "PATH:LINE: XML syntax
// error: ...", "PATH:LINE: neither URDF (<robot>) nor SDF (<sdf>): ...".
Result<RobotXml> read_robot_xml(const std::string &path);

// "FILE:LINE: message", or "FILE: message" when line is 0.
Error at(const std::string &file, int line, const std::string &message);

// A library's message on one line, trimmed: libsdformat's and urdfdom's
// may span several.
std::string one_line(std::string s);

} // namespace tcs::sim::robot
