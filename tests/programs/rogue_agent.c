/* rogue_agent DOMAIN NAME STEP_NS EFFORT POSITION POSE GOOD_FROM STEPS: an
 * agent of the step protocol (coordinatord/dds/idl/tcs_step.idl) that is no
 * coordinatord, for tests/process/test_agent_commands.py. It joins the
 * world on the DDS domain and answers STEPS grants; every answer carries
 * commands a host must not take (docs/DESIGN.md §7: "only finite commands
 * to scalar actuator signals within the step"): NaN and infinite efforts,
 * a position (no actuator), a pose (not scalar), a signal the world lacks,
 * efforts before and after the step. From grant GOOD_FROM on, one finite
 * effort of 2 N*m comes first in each answer, so that a bad one after it,
 * were it taken, would replace it. Signals are given by their index in
 * the world's table. Prints answered=N and good_at=T, the time of the grant
 * whose answer first carried the good command. Exit 0 when done, 1 on a
 * DDS failure. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include <dds/dds.h>

#include "tcs_step.h"

/* The host's QoS for the protocol's topics (coordinatord/dds/step_link.cc):
 * a reader or writer must offer as much to be matched. */
static dds_qos_t *qos(int keep_all, int transient)
{
	dds_qos_t *q = dds_create_qos();
	dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
	if (keep_all)
		dds_qset_history(q, DDS_HISTORY_KEEP_ALL, 0);
	else
		dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 1);
	dds_qset_durability(q, transient ? DDS_DURABILITY_TRANSIENT_LOCAL : DDS_DURABILITY_VOLATILE);
	dds_qset_liveliness(q, DDS_LIVELINESS_AUTOMATIC, DDS_SECS(1));
	const dds_data_representation_id_t xcdr2 = DDS_DATA_REPRESENTATION_XCDR2;
	dds_qset_data_representation(q, 1, &xcdr2);
	return q;
}

static int fail(const char *what, dds_return_t rc)
{
	fprintf(stderr, "rogue_agent: %s: %s\n", what, dds_strretcode(rc));
	return 1;
}

/* Waits (10 s at most) for a sample on reader; 1 if one came. */
static int wait_for(dds_entity_t participant, dds_entity_t reader)
{
	dds_entity_t ws = dds_create_waitset(participant);
	dds_entity_t cond = dds_create_readcondition(reader, DDS_ANY_STATE);
	dds_waitset_attach(ws, cond, 0);
	dds_return_t n = dds_waitset_wait(ws, NULL, 0, DDS_SECS(10));
	dds_delete(ws);
	return n > 0;
}

int main(int argc, char **argv)
{
	if (argc != 9) {
		fprintf(stderr, "usage: rogue_agent DOMAIN NAME STEP_NS EFFORT POSITION POSE GOOD_FROM STEPS\n");
		return 2;
	}
	const uint32_t domain = (uint32_t)atoi(argv[1]);
	char *name = argv[2];
	const int64_t step_ns = atoll(argv[3]);
	const uint32_t effort = (uint32_t)atoi(argv[4]), position = (uint32_t)atoi(argv[5]),
		       pose = (uint32_t)atoi(argv[6]);
	const uint64_t good_from = strtoull(argv[7], NULL, 10), steps = strtoull(argv[8], NULL, 10);

	dds_entity_t p = dds_create_participant(domain, NULL, NULL);
	if (p < 0)
		return fail("participant", p);
	dds_entity_t world_t = dds_create_topic(p, &tcs_dds__HostedWorld_desc, tcs_dds__WORLD_TOPIC, NULL, NULL);
	dds_entity_t grant_t = dds_create_topic(p, &tcs_dds__StepGrant_desc, tcs_dds__STEP_GRANT_TOPIC, NULL, NULL);
	dds_entity_t done_t = dds_create_topic(p, &tcs_dds__StepDone_desc, tcs_dds__STEP_DONE_TOPIC, NULL, NULL);
	if (world_t < 0 || grant_t < 0 || done_t < 0)
		return fail("topics", world_t < 0 ? world_t : grant_t < 0 ? grant_t : done_t);
	dds_qos_t *q = qos(0, 1);
	dds_entity_t worlds = dds_create_reader(p, world_t, q, NULL);
	dds_entity_t grants = dds_create_reader(p, grant_t, q, NULL);
	dds_delete_qos(q);
	q = qos(1, 0);
	dds_entity_t answers = dds_create_writer(p, done_t, q, NULL);
	dds_delete_qos(q);
	if (worlds < 0 || grants < 0 || answers < 0)
		return fail("readers and writer", worlds < 0 ? worlds : grants < 0 ? grants : answers);

	/* The world's id, from the host's publication of it. */
	uint32_t world = 0;
	for (int found = 0; !found;) {
		if (!wait_for(p, worlds))
			return fail("no world published", DDS_RETCODE_TIMEOUT);
		void *samples[1] = { NULL };
		dds_sample_info_t info;
		if (dds_take(worlds, samples, &info, 1, 1) == 1 && info.valid_data) {
			world = ((tcs_dds__HostedWorld *)samples[0])->world;
			found = 1;
		}
		if (samples[0])
			dds_return_loan(worlds, samples, 1);
	}
	/* Joined once the host's reader of answers has matched the writer:
	 * a volatile sample written before that is nobody's. */
	for (int i = 0;; i++) {
		dds_publication_matched_status_t m;
		dds_get_publication_matched_status(answers, &m);
		if (m.current_count > 0)
			break;
		if (i == 1000)
			return fail("the host's reader never matched", DDS_RETCODE_TIMEOUT);
		dds_sleepfor(DDS_MSECS(10));
	}
	tcs_dds__StepDone done = { 0 };
	done.world = world;
	done.agent = name;
	done.step = UINT64_MAX;
	done.next_event_ns = INT64_MAX;
	if (dds_write(answers, &done) < 0)
		return fail("joining", DDS_RETCODE_ERROR);

	uint64_t answered = 0, last = UINT64_MAX;
	int64_t good_at = -1; /* the grant's time whose answer first had the good command */
	while (answered < steps) {
		if (!wait_for(p, grants))
			return fail("no grant", DDS_RETCODE_TIMEOUT);
		void *samples[1] = { NULL };
		dds_sample_info_t info;
		if (dds_take(grants, samples, &info, 1, 1) != 1)
			continue;
		const tcs_dds__StepGrant g = *(tcs_dds__StepGrant *)samples[0];
		const int valid = info.valid_data && g.world == world && g.step != last;
		dds_return_loan(grants, samples, 1);
		if (!valid)
			continue;
		last = g.step;
		const int64_t s = g.sim_ns, mid = g.sim_ns + step_ns / 2;
		tcs_dds__Command c[10];
		uint32_t n = 0;
		if (answered == good_from)
			good_at = s;
		if (answered >= good_from)
			c[n++] = (tcs_dds__Command){ s + step_ns / 4, effort, 2.0 };
		c[n++] = (tcs_dds__Command){ mid, effort, NAN };
		c[n++] = (tcs_dds__Command){ mid, effort, INFINITY };
		c[n++] = (tcs_dds__Command){ mid, effort, -INFINITY };
		c[n++] = (tcs_dds__Command){ mid, position, 1.0 };
		c[n++] = (tcs_dds__Command){ mid, pose, 1.0 };
		c[n++] = (tcs_dds__Command){ mid, 100000, 1.0 };
		c[n++] = (tcs_dds__Command){ s - 1, effort, 5.0 };
		c[n++] = (tcs_dds__Command){ s + 2 * step_ns, effort, 5.0 };
		done.step = g.step;
		done.next_event_ns = s + step_ns;
		done.commands = (dds_sequence_tcs_dds__Command){ n, n, c, false };
		if (dds_write(answers, &done) < 0)
			return fail("answering", DDS_RETCODE_ERROR);
		answered++;
	}
	done.step = UINT64_MAX - 1; /* leaving */
	done.commands = (dds_sequence_tcs_dds__Command){ 0, 0, NULL, false };
	dds_write(answers, &done);
	dds_wait_for_acks(answers, DDS_SECS(5));
	dds_delete(p);
	printf("answered=%llu good_at=%lld\n", (unsigned long long)answered, (long long)good_at);
	return 0;
}
