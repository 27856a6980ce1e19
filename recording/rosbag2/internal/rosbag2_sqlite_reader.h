// SPDX-License-Identifier: Apache-2.0
#pragma once
// rosbag2 recordings: one sqlite3 storage file (.db3), or a rosbag2 folder whose metadata.yaml
// lists its storage files in recording order (sqlite3 or mcap storage; each .mcap goes through
// recording/mcap/internal/mcap_reader.h). The database is opened read-only (SQLITE_OPEN_READONLY) and never changed.
//
// Layouts: tables `topics` (id, name, type, serialization_format, offered_qos_profiles
// [, type_description_hash]) and `messages` (id, topic_id, timestamp [ns since the epoch], data)
// as Humble writes them; Iron and later add `message_definitions`, `schema` and `metadata`, which
// are not needed to read messages. Messages are passed on in timestamp order (ties: messages.id);
// RecordedMessage::file_offset carries messages.id, which error messages quote as the message
// index. A folder without metadata.yaml (a recorder that crashed, or one still recording) is
// read from the .db3/.mcap files it holds, in split order (rosbag2_folder.h), with a warning;
// with metadata.yaml, the storage files it does not list (written after it, at a split) are
// read after those it lists, with a warning. Compressed bags (compression_mode FILE or MESSAGE)
// throw io::InputError.

#include <memory>
#include <string>

#include "recording/recording.h"

namespace wallcal::recording {

// `path`: a .db3 file or a rosbag2 folder (a lone .mcap file opens too, by its magic). Throws
// io::InputError when it is neither, when a table is missing (a database that is not rosbag2), or
// when a listed storage file is missing.
std::unique_ptr<Recording> OpenRosbag2(const std::string& path);

// A .db3 file still being written, read on from the rows after the last one read
// (recording/recording_tail.h; rosbag2_sqlite_tail.cc).
class RecordingTail;
std::unique_ptr<RecordingTail> OpenRosbag2SqliteTail(const std::string& path);

}  // namespace wallcal::recording
