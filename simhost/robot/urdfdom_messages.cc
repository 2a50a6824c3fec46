// UrdfdomMessages: console_bridge's handler for the time of one load.
#include "urdfdom_messages.h"

namespace tcs::sim::robot {

UrdfdomMessages::UrdfdomMessages()
{
	console_bridge::useOutputHandler(this);
}

UrdfdomMessages::~UrdfdomMessages()
{
	console_bridge::restorePreviousOutputHandler();
}

void UrdfdomMessages::log(const std::string &text, console_bridge::LogLevel level, const char *, int)
{
	if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR && first_.empty())
		first_ = text;
}

} // namespace tcs::sim::robot
