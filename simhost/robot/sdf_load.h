// A robot file (URDF or SDF) read into a description, through Debian's
// libsdformat 12, which also converts URDF to SDF (docs/DESIGN.md §8).
//
// What a file becomes:
//  - SDF: its <model>, or each <model> of its <world> with the world's
//    <gravity> and <physics><max_step_size> (when the file gives them);
//    link order as in the file, the canonical link first.
//  - URDF: one model, links from the root down (links[0] is the root).
//    Fixed joints are lumped as Gazebo does: a link fixed to another
//    becomes part of it (mass, inertia and collisions), and its name and
//    its fixed joint are gone; its sensors move to the link it joins.
//    Joints to the world stay. A continuous joint stays continuous.
//  - A massless fixed base is kept (urdf_prepare.h): a massless URDF root
//    is welded to the world by an added fixed joint `world_to_ROOT`, and a
//    massless link welded to the world keeps what it carries. Such links
//    have mass 0 in the description; a link of mass 0 is always welded to
//    the world (a fixed joint with parent "world") or in a static model,
//    so the physics can attach its collisions to the world.
//  - Limits: none when the file has none (SDF's +-1e16 default, or any
//    bound beyond it, counts as none); effort and velocity limits absent
//    when <= 0 or infinite.
//  - Sensors: imu, force_torque (on a joint; its link is the joint's
//    child), contact, and ray/gpu_ray/lidar (as ray, with its range).
//    Other sensor types (cameras, GPS, ...) are left out: tcs has no
//    signal for them.
//  - Collision meshes: STL (binary, ASCII) and OBJ files (mesh_load.h),
//    scaled by the file's scale, their URI (relative, file://, package://,
//    model://) found as mesh_uri.h says; a URDF's at the line of its
//    <mesh>. Visuals are not read, so their meshes are never looked for.
//
// Refused, as one line "FILE:LINE: message" (FILE as given; "FILE: message"
// where no line is known): a missing file, XML that is not well formed,
// what libsdformat or urdfdom refuse, joint types other than revolute,
// continuous, prismatic, fixed, ball and universal ("tcs cannot simulate
// joint type X"), a mesh not found ("mesh 'URI' not found (looked in:
// ...)"), one load_mesh refuses (other formats, damaged files), an SDF
// <submesh>, heightmaps, nested models, joint loops,
// unknown links, duplicate names, masses that are not finite and
// non-negative, a moving link without mass or with an inertia that is not
// positive definite.
//
// libsdformat's console is silenced (and urdfdom's messages are captured
// for the error), so nothing is printed; libsdformat itself still writes
// its debug log to ~/.sdformat/sdformat.log, which it opens on first use.
#pragma once

#include <string>

#include "description.h"
#include "error.h"

namespace tcs::sim::robot {

Result<Description> load_robot_file(const std::string &path);

} // namespace tcs::sim::robot
