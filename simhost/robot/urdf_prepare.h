// A URDF made ready for libsdformat's converter, and what its own text
// says that the conversion loses. The converter (sdformat 12) refuses or
// silently drops what users write every day, so the URDF is checked and
// mended first, with tinyxml2, where each element's line is known:
//
//  - a joint whose parent is `world` without a <link name="world"/> (Drake,
//    Bullet): world is declared, the joint becomes one to the world;
//  - a massless link (no <inertial>, or a mass below libsdformat's 1e-6
//    kg) is dropped by the converter with everything it carries. When it
//    is the root, or is welded to the world, and nothing fixed to it has
//    mass either, it is a fixed base (Bullet's "mass 0 root", Drake's
//    welded base_link): it is given a stand-in inertial for the converter
//    and is massless again in the description; a massless root is welded
//    to the world by an added fixed joint (world_to_ROOT). A massless link
//    that moves is refused, and so is a massless link fixed to another
//    that carries further joints (the converter would drop them);
//  - a collision mesh's filename (package://, model://, relative) is
//    resolved here, at its line (mesh_uri.h), and the file's path written
//    in its place: the converter would turn package:// into model://;
//  - a joint naming an undeclared link, a link that is the child of two
//    joints, a loop of joints, duplicate names, a mass that is not a
//    finite non-negative number, joint types tcs cannot simulate: refused
//    with their line, where urdfdom would say only "Failed to build tree".
#pragma once

#include <map>
#include <set>
#include <string>

#include <tinyxml2.h>

#include "error.h"

namespace tcs::sim::robot {

struct UrdfFacts {
	// Lines of the file's declarations, by name.
	std::map<std::string, int> link_line, joint_line, sensor_line;
	// Each joint's URDF type: SDF has no continuous joint from URDF (it
	// becomes a revolute one with +-1e16 limits).
	std::map<std::string, std::string> joint_type;
	// Links given a stand-in inertial: massless in the description.
	std::set<std::string> massless;
	std::string weld; // the fixed joint added to weld a massless root, or ""
	// Collision meshes by the path written in place of their URI: the URI
	// as the file wrote it, and the <mesh>'s line.
	struct MeshRef {
		std::string uri;
		int line = 0;
	};
	std::map<std::string, MeshRef> meshes;
};

// Checks and mends doc (a <robot> document read from file) in place.
Result<UrdfFacts> prepare_urdf(const std::string &file, tinyxml2::XMLDocument &doc);

} // namespace tcs::sim::robot
