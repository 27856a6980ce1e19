// SPDX-License-Identifier: Apache-2.0
#pragma once
// A rosbag2 folder's storage files, as a finished recording lists them and as one still being
// recorded holds them. `ros2 bag record -o NAME` writes NAME/NAME_0.db3 (or .mcap), starts
// NAME_1, NAME_2, ... at each split, and writes NAME/metadata.yaml when it stops (some releases
// at each split too), so a folder read while recording holds storage files that metadata.yaml
// does not list yet, or no metadata.yaml at all.

#include <memory>
#include <string>
#include <vector>

#include "io/config/rosbag2_metadata.h"

namespace wallcal::recording {

class RecordingTail;

// True for a folder holding a metadata.yaml or a .db3 or .mcap file.
bool IsRosbag2Folder(const std::string& folder);

// Orders names as rosbag2 numbers its split files: "bag_2.db3" before "bag_10.db3" (runs of
// digits compared as numbers).
bool SplitOrderLess(const std::string& a, const std::string& b);

struct Rosbag2Files {
  std::vector<std::string> paths;  // the storage files, in split order (folder/name)
  bool has_metadata = false;
  io::Rosbag2Metadata metadata;       // when has_metadata
  int listed = 0;                 // paths[0, listed) are those metadata.yaml lists, in its order;
                                  // the rest, not listed, follow by SplitOrderLess
};

// The storage files of `folder`: metadata.yaml's relative_file_paths (a path relative to the
// folder's parent, as early rosbag2 wrote them, is taken too), then the .db3 and .mcap files it
// does not list. Throws io::InputError for a metadata.yaml that does not parse (io/config/rosbag2_metadata.h),
// a compressed bag (compression_format or compression_mode set), or a listed file the folder
// lacks.
Rosbag2Files FindRosbag2Files(const std::string& folder);

// A rosbag2 folder still being recorded, read on file by file (recording/recording_tail.h;
// rosbag2_folder_tail.cc).
std::unique_ptr<RecordingTail> OpenRosbag2FolderTail(const std::string& folder);

}  // namespace wallcal::recording
