/* clock_listen DOMAIN COUNT TIMEOUT_S [--joints]: a DDS subscriber to what
 * tcs publishes for ROS 2 (rt/clock, or rt/joint_states with --joints), so
 * tests can check it without ROS 2. Prints "ready" once its reader exists,
 * then "type TYPENAME" with the type name the matched publication announced
 * in discovery (DCPSPublication), then one line per sample:
 *   clock SEC NANOSEC
 *   joints SEC NANOSEC N name=position,velocity ...
 * Exits 0 after COUNT samples, 1 if TIMEOUT_S pass first, 2 on misuse. */
#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <dds/dds.h>

#include "ros_clock.h"
#include "ros_joint_state.h"

#define BATCH 16

static int parse(const char *s, long max, long *out)
{
	char *end;
	errno = 0;
	*out = strtol(s, &end, 10);
	return errno == 0 && end != s && *end == '\0' && *out >= 0 && *out <= max;
}

/* The publisher's entry in DCPSPublication: its instance there is the
 * publication_handle of the samples it sent. */
static void print_type(dds_entity_t publications, dds_instance_handle_t writer)
{
	void *buf[1] = { NULL };
	dds_sample_info_t info;
	if (dds_read_instance(publications, buf, &info, 1, 1, writer) == 1 && info.valid_data) {
		const dds_builtintopic_endpoint_t *ep = buf[0];
		printf("type %s\n", ep->type_name);
	} else {
		printf("type ?\n");
	}
	dds_return_loan(publications, buf, 1);
}

static void print_value(const dds_sequence_double *s, uint32_t i)
{
	if (i < s->_length)
		printf("%.17g", s->_buffer[i]);
	else
		printf("-");
}

static void print_sample(int joints, const void *sample)
{
	if (!joints) {
		const rosgraph_msgs_msg_dds__Clock_ *c = sample;
		printf("clock %" PRId32 " %" PRIu32 "\n", c->clock.sec, c->clock.nanosec);
		return;
	}
	const sensor_msgs_msg_dds__JointState_ *j = sample;
	printf("joints %" PRId32 " %" PRIu32 " %" PRIu32, j->header.stamp.sec, j->header.stamp.nanosec, j->name._length);
	for (uint32_t i = 0; i < j->name._length; i++) {
		printf(" %s=", j->name._buffer[i]);
		print_value(&j->position, i);
		printf(",");
		print_value(&j->velocity, i);
	}
	printf("\n");
}

int main(int argc, char **argv)
{
	long domain, count, timeout_s;
	int joints = argc == 5 && strcmp(argv[4], "--joints") == 0;
	if ((argc != 4 && !joints) || !parse(argv[1], 232, &domain) || !parse(argv[2], 1000000000, &count) ||
	    !parse(argv[3], 1000000, &timeout_s)) {
		fprintf(stderr, "usage: clock_listen DOMAIN COUNT TIMEOUT_S [--joints]\n");
		return 2;
	}
	const dds_time_t deadline = dds_time() + DDS_SECS(timeout_s);

	dds_entity_t pp = dds_create_participant((dds_domainid_t)domain, NULL, NULL);
	if (pp < 0) {
		fprintf(stderr, "clock_listen: creating the participant: %s\n", dds_strretcode(pp));
		return 2;
	}
	dds_entity_t topic = joints ?
		dds_create_topic(pp, &sensor_msgs_msg_dds__JointState__desc, "rt/joint_states", NULL, NULL) :
		dds_create_topic(pp, &rosgraph_msgs_msg_dds__Clock__desc, "rt/clock", NULL, NULL);
	/* Reliable, to match tcs's reliable writers and to miss nothing the
	 * test counts; keep all, so a slow test machine loses nothing either. */
	dds_qos_t *qos = dds_create_qos();
	dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
	dds_qset_history(qos, DDS_HISTORY_KEEP_ALL, 0);
	const dds_data_representation_id_t xcdr1 = DDS_DATA_REPRESENTATION_XCDR1;
	dds_qset_data_representation(qos, 1, &xcdr1);
	dds_entity_t reader = topic < 0 ? topic : dds_create_reader(pp, topic, qos, NULL);
	dds_delete_qos(qos);
	dds_entity_t publications = dds_create_reader(pp, DDS_BUILTIN_TOPIC_DCPSPUBLICATION, NULL, NULL);
	dds_entity_t ws = dds_create_waitset(pp);
	dds_entity_t ready = reader < 0 ? reader : dds_create_readcondition(reader, DDS_ANY_STATE);
	if (reader < 0 || publications < 0 || ws < 0 || ready < 0 || dds_waitset_attach(ws, ready, 0) < 0) {
		fprintf(stderr, "clock_listen: setting up the reader failed\n");
		dds_delete(pp);
		return 2;
	}
	printf("ready\n");
	fflush(stdout);

	long got = 0;
	int typed = 0;
	while (got < count) {
		void *buf[BATCH] = { NULL };
		dds_sample_info_t info[BATCH];
		dds_return_t n = dds_take(reader, buf, info, BATCH, BATCH);
		for (dds_return_t i = 0; i < n && got < count; i++) {
			if (!info[i].valid_data)
				continue;
			if (!typed) {
				print_type(publications, info[i].publication_handle);
				typed = 1;
			}
			print_sample(joints, buf[i]);
			got++;
		}
		if (n > 0)
			dds_return_loan(reader, buf, n);
		fflush(stdout);
		if (got < count && n <= 0 && dds_waitset_wait_until(ws, NULL, 0, deadline) == 0) {
			fprintf(stderr, "clock_listen: timed out after %ld s with %ld of %ld samples\n", timeout_s, got,
				count);
			dds_delete(pp);
			return 1;
		}
	}
	dds_delete(pp);
	return 0;
}
