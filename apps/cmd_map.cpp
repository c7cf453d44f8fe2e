// sgslam map info FILE: what a saved map (sgslam run --save-map) holds.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "commands.h"
#include "sgslam/common/stats.h"
#include "sgslam/mapfile/map_file.h"

namespace sgslam::app {

Action AddMapCommand(CLI::App& root) {
  CLI::App* cmd = root.add_subcommand("map", "Inspect a map saved by sgslam run --save-map");
  cmd->require_subcommand(1);
  auto file = std::make_shared<std::string>();
  CLI::App* info = cmd->add_subcommand("info", "Check a map file and print what it holds");
  info->add_option("FILE", *file, "Map file")->required();
  return [file] {
    const Stopwatch watch;
    const mapfile::MapData data = mapfile::ReadMapFile(*file);
    const double ms = watch.ElapsedMs();
    std::error_code ec;  // the file read a moment ago: a size gone meanwhile is no error of the map's
    const std::uintmax_t bytes = std::filesystem::file_size(*file, ec);
    std::printf("%s: %.1f MB, read and checked in %.0f ms\n%s", file->c_str(), ec ? 0.0 : static_cast<double>(bytes) / 1e6,
                ms, mapfile::Describe(data).c_str());
    return kExitOk;
  };
}

}  // namespace sgslam::app
