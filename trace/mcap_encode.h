// How the writer lays records out: little-endian fields appended to byte
// vectors (of any allocator: the chunk's grows without zeroing), records whose length is filled in once their content is there,
// and the Schema and Channel records it writes both in chunks and in the
// summary. MCAP format version 0: every record is <opcode u8><content
// length u64><content>; strings and arrays are prefixed with their byte
// length as u32.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "mcap_format.h"

// Its own namespace: these short names are the writer's, no one else's.
namespace tcs::mcap_encode {

inline void store_le(uint8_t *p, uint64_t v, int bytes)
{
	for (int i = 0; i < bytes; i++)
		p[i] = uint8_t(v >> (8 * i));
}

template <class Bytes> void put_le(Bytes &b, uint64_t v, int bytes)
{
	uint8_t tmp[8];
	store_le(tmp, v, bytes);
	b.insert(b.end(), tmp, tmp + bytes);
}

template <class Bytes> void put_u8(Bytes &b, uint8_t v) { b.push_back(v); }
template <class Bytes> void put_u16(Bytes &b, uint16_t v) { put_le(b, v, 2); }
template <class Bytes> void put_u32(Bytes &b, uint32_t v) { put_le(b, v, 4); }
template <class Bytes> void put_u64(Bytes &b, uint64_t v) { put_le(b, v, 8); }

template <class Bytes> void put_bytes(Bytes &b, const void *data, size_t size)
{
	const uint8_t *p = static_cast<const uint8_t *>(data);
	b.insert(b.end(), p, p + size);
}

// Callers have checked that s fits a u32 length.
template <class Bytes> void put_string(Bytes &b, std::string_view s)
{
	put_u32(b, uint32_t(s.size()));
	put_bytes(b, s.data(), s.size());
}

// Starts a record; returns where its content length goes, which
// end_record() fills in once the content is there.
template <class Bytes> size_t begin_record(Bytes &b, McapOpcode op)
{
	put_u8(b, op);
	size_t at = b.size();
	put_u64(b, 0);
	return at;
}

template <class Bytes> void end_record(Bytes &b, size_t at)
{
	store_le(b.data() + at, b.size() - at - 8, 8);
}

// The bytes of a Channel's metadata map, as its u32 length prefix counts them.
inline uint64_t metadata_bytes(const std::map<std::string, std::string> &m)
{
	uint64_t n = 0;
	for (const auto &[k, v] : m)
		n += 4 + k.size() + 4 + v.size();
	return n;
}

// A Schema record of id; SchemaT has name, encoding and data.
template <class Bytes, class SchemaT> void put_schema(Bytes &b, uint16_t id, const SchemaT &s)
{
	size_t at = begin_record(b, mcap_schema);
	put_u16(b, id);
	put_string(b, s.name);
	put_string(b, s.encoding);
	put_string(b, s.data);
	end_record(b, at);
}

// A Channel record of id; ChannelT has schema_id, topic, message_encoding
// and metadata. Callers have checked that the metadata fits a u32 length.
template <class Bytes, class ChannelT> void put_channel(Bytes &b, uint16_t id, const ChannelT &c)
{
	size_t at = begin_record(b, mcap_channel);
	put_u16(b, id);
	put_u16(b, c.schema_id);
	put_string(b, c.topic);
	put_string(b, c.message_encoding);
	put_u32(b, uint32_t(metadata_bytes(c.metadata)));
	for (const auto &[k, v] : c.metadata) {
		put_string(b, k);
		put_string(b, v);
	}
	end_record(b, at);
}

} // namespace tcs::mcap_encode
