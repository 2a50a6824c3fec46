// What a robot file's XML says before libsdformat reads it: the line of
// each named link and joint (libsdformat 12 gives many of its errors no
// line), the number of links, refused past max_links (libsdformat needs
// about 1.5 MB and 10 ms for each link: 10,000 links would take 15 GB and
// minutes), and each SDF <mass> checked to be a finite, non-negative
// number (libsdformat says only "invalid inertia").
#pragma once

#include <map>
#include <string>

#include <tinyxml2.h>

#include "error.h"

namespace tcs::sim::robot {

constexpr int max_links = 1000;

struct XmlFacts {
	// The last declaration of each name (the one a "declared twice"
	// error is about).
	std::map<std::string, int> link_line, joint_line;
	int links = 0;
};

Result<XmlFacts> read_xml_facts(const std::string &file, const tinyxml2::XMLDocument &doc);

// The line of the link or joint that a message of libsdformat or urdfdom
// names ("name[x]", "[x]", "named x"), or 0.
int line_named(const XmlFacts &f, const std::string &message);

} // namespace tcs::sim::robot
