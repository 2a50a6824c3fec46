// urdfdom's reasons, kept: urdfdom (inside libsdformat's URDF converter)
// says why a URDF cannot be read through console_bridge, on stderr, and
// libsdformat then reports only "Unable to read file". While one of these
// lives, console_bridge's messages come here instead, and nothing is
// printed.
#pragma once

#include <string>

#include <console_bridge/console.h>

namespace tcs::sim::robot {

class UrdfdomMessages : public console_bridge::OutputHandler {
public:
	UrdfdomMessages();
	~UrdfdomMessages() override;
	UrdfdomMessages(const UrdfdomMessages &) = delete;
	UrdfdomMessages &operator=(const UrdfdomMessages &) = delete;
	void log(const std::string &text, console_bridge::LogLevel level, const char *file, int line) override;

	const std::string &first_error() const { return first_; }

private:
	std::string first_;
};

} // namespace tcs::sim::robot
