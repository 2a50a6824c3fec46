// DdsStepHost and DdsStepAgent: the DDS entities of the step protocol,
// their QoS, and the samples converted to and from step_peers.h.
#include "step_link.h"

#include <sys/eventfd.h>
#include <unistd.h>

#include <dds/dds.h>

#include "tcs_step.h"
#include "unique_fd.h"

namespace tcs {

namespace {

Error dds_error(const std::string &what, dds_return_t rc)
{
	return Error{ "DDS: " + what + ": " + dds_strretcode(rc) };
}

// Reliable: nothing of the protocol may be lost. XCDR2: the types are
// @appendable (idl/tcs_step.idl). Liveliness: a peer that dies is seen
// gone within the lease.
dds_qos_t *step_qos(bool keep_all, bool transient)
{
	dds_qos_t *q = dds_create_qos();
	dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
	if (keep_all)
		dds_qset_history(q, DDS_HISTORY_KEEP_ALL, 0);
	else
		dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 1);
	dds_qset_durability(q, transient ? DDS_DURABILITY_TRANSIENT_LOCAL : DDS_DURABILITY_VOLATILE);
	dds_qset_liveliness(q, DDS_LIVELINESS_AUTOMATIC, kStepLeaseNs);
	const dds_data_representation_id_t xcdr2 = DDS_DATA_REPRESENTATION_XCDR2;
	dds_qset_data_representation(q, 1, &xcdr2);
	return q;
}

// The QoS of each topic. Grants: the newest only, kept for an agent that
// joins late (it starts from the world's present); the host writes the
// next only when every agent has answered this one, so none is ever
// overwritten unread. Answers: every one, in order. The world: the newest.
dds_qos_t *grant_qos() { return step_qos(false, true); }
dds_qos_t *done_qos() { return step_qos(true, false); }
dds_qos_t *world_qos() { return step_qos(false, true); }

// A participant, and an eventfd its listeners write to when something
// arrives or a peer's liveliness changes.
class Endpoint {
public:
	~Endpoint()
	{
		if (participant > 0)
			dds_delete(participant);
		if (listener)
			dds_delete_listener(listener);
	}
	Status open(uint32_t domain)
	{
		wake.reset(eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK));
		if (!wake)
			return errno_error("eventfd");
		participant = dds_create_participant(domain, nullptr, nullptr);
		if (participant < 0) {
			dds_return_t rc = participant;
			participant = 0;
			return dds_error("creating the participant in domain " + std::to_string(domain), rc);
		}
		listener = dds_create_listener(this);
		dds_lset_data_available(listener, [](dds_entity_t, void *self) { static_cast<Endpoint *>(self)->poke(); });
		dds_lset_liveliness_changed(listener, [](dds_entity_t, const dds_liveliness_changed_status_t, void *self) {
			static_cast<Endpoint *>(self)->poke();
		});
		return Ok{};
	}
	// The participant and the protocol's three topics.
	Status open_topics(uint32_t domain)
	{
		if (auto s = open(domain); !s)
			return s;
		auto w = topic(&tcs_dds__HostedWorld_desc, tcs_dds__WORLD_TOPIC);
		auto g = topic(&tcs_dds__StepGrant_desc, tcs_dds__STEP_GRANT_TOPIC);
		auto d = topic(&tcs_dds__StepDone_desc, tcs_dds__STEP_DONE_TOPIC);
		for (auto *t : { &w, &g, &d })
			if (!*t)
				return t->error();
		world_topic = *w;
		grant_topic = *g;
		done_topic = *d;
		return Ok{};
	}
	Result<dds_entity_t> topic(const dds_topic_descriptor_t *desc, const char *name)
	{
		dds_entity_t t = dds_create_topic(participant, desc, name, nullptr, nullptr);
		if (t < 0)
			return dds_error(std::string("creating topic ") + name, t);
		return t;
	}
	Result<dds_entity_t> writer(dds_entity_t topic, dds_qos_t *q)
	{
		dds_entity_t w = dds_create_writer(participant, topic, q, nullptr);
		dds_delete_qos(q);
		if (w < 0)
			return dds_error("creating a writer", w);
		return w;
	}
	// A reader whose arrivals wake the loop (listened) or not.
	Result<dds_entity_t> reader(dds_entity_t topic, dds_qos_t *q, bool listened)
	{
		dds_entity_t r = dds_create_reader(participant, topic, q, listened ? listener : nullptr);
		dds_delete_qos(q);
		if (r < 0)
			return dds_error("creating a reader", r);
		return r;
	}
	void poke()
	{
		uint64_t one = 1;
		(void)!write(wake.get(), &one, sizeof one);
	}
	void drain()
	{
		uint64_t n;
		(void)!read(wake.get(), &n, sizeof n);
	}
	dds_entity_t participant = 0;
	dds_entity_t world_topic = 0, grant_topic = 0, done_topic = 0;
	dds_listener_t *listener = nullptr;
	UniqueFd wake;
};

// Takes every sample there is, valid or not, and gives each to f.
template <class T, class F> void take_all(dds_entity_t reader, F f)
{
	for (;;) {
		void *samples[16] = {};
		dds_sample_info_t infos[16];
		dds_return_t n = dds_take(reader, samples, infos, 16, 16);
		if (n <= 0)
			return;
		for (dds_return_t i = 0; i < n; i++)
			f(*static_cast<const T *>(samples[i]), infos[i]);
		dds_return_loan(reader, samples, n);
	}
}

bool gone(const dds_sample_info_t &info)
{
	return info.instance_state != DDS_IST_ALIVE;
}

class DdsStepHost : public StepHost {
public:
	Status open(uint32_t domain, const HostedWorldInfo &w)
	{
		world_ = w.world;
		if (auto s = ep_.open_topics(domain); !s)
			return s;
		auto world_writer = ep_.writer(ep_.world_topic, world_qos());
		auto grant_writer = ep_.writer(ep_.grant_topic, grant_qos());
		auto done_reader = ep_.reader(ep_.done_topic, done_qos(), true);
		for (auto *e : { &world_writer, &grant_writer, &done_reader })
			if (!*e)
				return e->error();
		grants_ = *grant_writer;
		answers_ = *done_reader;
		tcs_dds__HostedWorld sample{ w.world, const_cast<char *>(w.host.c_str()),
					     const_cast<char *>(w.scenario.c_str()), w.mode };
		if (dds_return_t rc = dds_write(*world_writer, &sample); rc < 0)
			return dds_error("publishing the world", rc);
		return Ok{};
	}
	int fd() const override { return ep_.wake.get(); }
	void grant(const Grant &g) override
	{
		tcs_dds__StepGrant s{};
		s.world = world_;
		s.step = g.step;
		s.sim_ns = g.sim_ns;
		auto n = (uint32_t)g.signals.size();
		s.signals = { n, n, const_cast<double *>(g.signals.data()), false };
		(void)dds_write(grants_, &s);
	}
	void take(std::vector<Done> &answers, std::vector<std::string> &lost) override
	{
		ep_.drain();
		take_all<tcs_dds__StepDone>(answers_, [&](const tcs_dds__StepDone &s, const dds_sample_info_t &info) {
			if (s.world != world_)
				return;
			std::string agent = s.agent ? s.agent : "";
			if (!info.valid_data) {
				if (gone(info))
					lost.push_back(agent);
				return;
			}
			Done d;
			d.agent = agent;
			d.step = s.step;
			for (uint32_t i = 0; i < s.commands._length; i++)
				d.commands.push_back({ s.commands._buffer[i].v_ns, s.commands._buffer[i].signal,
						       s.commands._buffer[i].value });
			for (uint32_t i = 0; i < s.controllers._length; i++)
				d.controllers.emplace_back(s.controllers._buffer[i] ? s.controllers._buffer[i] : "");
			answers.push_back(std::move(d));
		});
	}

private:
	Endpoint ep_;
	uint32_t world_ = 0;
	dds_entity_t grants_ = 0, answers_ = 0;
};

class DdsStepAgent : public StepAgent {
public:
	Result<HostedWorldInfo> open(uint32_t domain, const std::string &agent, int64_t timeout_ns)
	{
		agent_ = agent;
		if (auto s = ep_.open_topics(domain); !s)
			return s.error();
		auto world_reader = ep_.reader(ep_.world_topic, world_qos(), false);
		if (!world_reader)
			return world_reader.error();
		HostedWorldInfo w;
		if (auto s = wait_world(*world_reader, timeout_ns, w); !s)
			return s.error();
		world_ = w.world;
		auto grant_reader = ep_.reader(ep_.grant_topic, grant_qos(), true);
		auto done_writer = ep_.writer(ep_.done_topic, done_qos());
		for (auto *e : { &grant_reader, &done_writer })
			if (!*e)
				return e->error();
		grants_ = *grant_reader;
		answers_ = *done_writer;
		return w;
	}
	~DdsStepAgent() override
	{
		// Gone on purpose: the host is told, not left to find out.
		if (answers_ > 0) {
			Done leaving;
			leaving.step = Done::kLeaving;
			answer(leaving);
		}
	}
	int fd() const override { return ep_.wake.get(); }
	void answer(const Done &d) override
	{
		std::vector<tcs_dds__Command> commands;
		for (const auto &c : d.commands)
			commands.push_back({ c.v, c.signal, c.value });
		std::vector<char *> names;
		for (const auto &n : d.controllers)
			names.push_back(const_cast<char *>(n.c_str()));
		tcs_dds__StepDone s{};
		s.world = world_;
		s.agent = const_cast<char *>(agent_.c_str());
		s.step = d.step;
		s.next_event_ns = INT64_MAX;
		s.commands = { (uint32_t)commands.size(), (uint32_t)commands.size(), commands.data(), false };
		s.controllers = { (uint32_t)names.size(), (uint32_t)names.size(), names.data(), false };
		(void)dds_write(answers_, &s);
	}
	void take(std::vector<Grant> &grants, bool &host_lost) override
	{
		ep_.drain();
		take_all<tcs_dds__StepGrant>(grants_, [&](const tcs_dds__StepGrant &s, const dds_sample_info_t &info) {
			if (s.world != world_)
				return;
			if (!info.valid_data) {
				host_lost |= gone(info);
				return;
			}
			Grant g;
			g.step = s.step;
			g.sim_ns = s.sim_ns;
			g.signals.assign(s.signals._buffer, s.signals._buffer + s.signals._length);
			grants.push_back(std::move(g));
		});
	}

private:
	// The first world published on the domain (a waitset: no polling).
	Status wait_world(dds_entity_t reader, int64_t timeout_ns, HostedWorldInfo &w)
	{
		dds_entity_t ws = dds_create_waitset(ep_.participant);
		dds_entity_t cond = dds_create_readcondition(reader, DDS_ANY_STATE);
		dds_waitset_attach(ws, cond, 0);
		const dds_time_t deadline = dds_time() + timeout_ns;
		bool found = false;
		while (!found) {
			take_all<tcs_dds__HostedWorld>(reader, [&](const tcs_dds__HostedWorld &s, const dds_sample_info_t &info) {
				if (found || !info.valid_data)
					return;
				w.world = s.world;
				w.host = s.host ? s.host : "";
				w.scenario = s.scenario ? s.scenario : "";
				w.mode = s.mode;
				found = true;
			});
			if (!found && dds_waitset_wait_until(ws, nullptr, 0, deadline) <= 0)
				break;
		}
		dds_delete(ws);
		if (!found)
			return Error{ "no world on this DDS domain (is a coordinatord with --dds-domain serving one?)" };
		return Ok{};
	}

	Endpoint ep_;
	std::string agent_;
	uint32_t world_ = 0;
	dds_entity_t grants_ = 0, answers_ = 0;
};

} // namespace

Result<std::unique_ptr<StepHost>> open_step_host(uint32_t domain, const HostedWorldInfo &world)
{
	auto h = std::make_unique<DdsStepHost>();
	if (auto s = h->open(domain, world); !s)
		return s.error();
	return std::unique_ptr<StepHost>(std::move(h));
}

Result<AgentJoin> join_world(uint32_t domain, const std::string &agent, int64_t timeout_ns)
{
	auto a = std::make_unique<DdsStepAgent>();
	auto w = a->open(domain, agent, timeout_ns);
	if (!w)
		return w.error();
	return AgentJoin{ std::move(a), std::move(*w) };
}

} // namespace tcs
