#pragma once
// One entry point for every supported dataset: detects the format from the path.
#include <string>

#include "hdvio/core/sequence.h"
#include "hdvio/io/read_options.h"

namespace hdvio::io {

enum class DatasetFormat { kAsl, kBlackbird, kDido, kNeuroBem, kRosBag };

const char* formatName(DatasetFormat format);

// ASL: a folder with mav0/ or imu0/. Blackbird / DIDO: a folder with data.hdf5, or that file
// (told apart by their dataset names). NeuroBEM: a .csv whose header names its columns.
// ROS bag: a file starting with "#ROSBAG V" (see ros_bag.h).
// Throws InputError if the path is missing or matches no format.
DatasetFormat detectFormat(const std::string& path);

// options.bag_topics / options.calibration apply to ROS bags only; given for another format
// they are an InputError rather than silently ignored.
Sequence readSequence(const std::string& path, const ReadOptions& options = {});

}  // namespace hdvio::io
