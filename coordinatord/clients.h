// coordinatord's clients: each one a `tcs-run --connect` that asked for a
// controller. Its connection lives as long as the controller does: a
// signal it forwards goes to the controller, its end comes back as ENDED,
// and a client that goes away takes its controller with it. The world is
// held until the controllers the scenario expects have attached.
#pragma once

#include <sys/types.h>

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "attach_protocol.h"
#include "coordinator.h"
#include "scenario.h"
#include "unique_fd.h"

namespace tcs {

class Clients {
public:
	using Log = std::function<void(const std::string &)>;
	Clients(Coordinator &co, const Scenario &scenario, Log log);
	~Clients();
	// Serves the listening socket from the coordinator's loop.
	Status serve(UniqueFd listening);
	// The coordinator's report of a controller's end.
	void controller_ended(const ControllerReport &r);
	// What the world still waits for ("" when it runs).
	std::string waiting_for() const;
	// The programs an agent on another host runs now: they fill the
	// scenario's [[controller]] entries as local ones do.
	void agent_programs(const std::string &agent, const std::vector<std::string> &programs);

private:
	struct Expected {
		std::string program; // basename of the scenario's command
		std::optional<double> cpu_scale;
		bool attached = false;
	};
	struct Client {
		UniqueFd fd;
		std::string in;
		std::vector<UniqueFd> fds; // stdin, stdout, stderr of the RUN
		int controller = 0;        // its controller's id, once started
		std::string name;
		Expected *slot = nullptr; // the [[controller]] it fills
	};
	void on_accept();
	void on_readable(Client *c);
	void on_frame(Client &c, const AttachFrame &f);
	void start(Client &c, RunRequest req);
	void refuse(Client &c, const std::string &why);
	void close_client(Client *c);
	void leave_slot(Client &c);
	void release_if_complete();
	Expected *expected_for(const std::string &argv0);

	Coordinator &co_;
	Log log_;
	UniqueFd listening_;
	std::vector<std::unique_ptr<Client>> clients_;
	std::vector<Expected> expected_;
	std::map<std::string, std::vector<Expected *>> agent_slots_;
	bool held_ = false;
};

} // namespace tcs
