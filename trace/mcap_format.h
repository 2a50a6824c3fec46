// The facts of the MCAP format (https://mcap.dev/spec) that its writer
// (mcap_writer.cc) and the trace reader (mcap_reader.cc) share.
#pragma once

#include <cstddef>
#include <cstdint>

namespace tcs {

// At the start and at the end of every MCAP file.
inline constexpr uint8_t kMcapMagic[8] = { 0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n' };

// Every record: this opcode byte, then its content length (uint64), then
// the content.
enum McapOpcode : uint8_t {
	mcap_header = 0x01,
	mcap_footer = 0x02,
	mcap_schema = 0x03,
	mcap_channel = 0x04,
	mcap_message = 0x05,
	mcap_chunk = 0x06,
	mcap_message_index = 0x07,
	mcap_chunk_index = 0x08,
	mcap_attachment = 0x09,
	mcap_attachment_index = 0x0A,
	mcap_statistics = 0x0B,
	mcap_metadata = 0x0C,
	mcap_metadata_index = 0x0D,
	mcap_summary_offset = 0x0E,
	mcap_data_end = 0x0F,
};
inline constexpr size_t kMcapRecordHead = 1 + 8;

} // namespace tcs
