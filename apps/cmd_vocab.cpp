// `sgslam vocab train`: a vocabulary tree (src/sgslam/vocab/) from the ORB
// features of a set of images; `sgslam vocab info`: what a vocabulary file holds.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "commands.h"
#include "progress.h"
#include "vocab_eval.h"
#include "sgslam/common/error.h"
#include "sgslam/common/regular_file.h"
#include "sgslam/common/stats.h"
#include "sgslam/features/orb_extractor.h"
#include "sgslam/io/image_file.h"
#include "sgslam/io/output_plan.h"
#include "sgslam/io/text_file.h"
#include "sgslam/vocab/training.h"

namespace sgslam::app {

namespace fs = std::filesystem;

namespace {

struct VocabArgs {
  std::vector<std::string> images;
  std::string out, info;
  vocab::TrainingOptions options;
  int every = 1;
  int features = 1000;
};

bool IsImage(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".ppm" || ext == ".pgm" || ext == ".bmp";
}

// A list file: one image a line, "path" or "timestamp path" (TUM's rgb.txt),
// relative to the list's folder.
std::vector<fs::path> ReadList(const fs::path& list) {
  std::vector<fs::path> out;
  ForEachDataLine(list, [&](int, const std::vector<std::string_view>& tokens) {
    out.push_back(list.parent_path() / std::string(tokens.back()));
  });
  return out;
}

// The images of one --images source: a list file, a TUM folder (its rgb.txt),
// or a folder of images (sorted by name).
std::vector<fs::path> ImagesOf(const fs::path& source) {
  std::error_code ec;
  if (!fs::is_directory(source, ec)) {
    if (WhyNotRegularFile(source) == kNotFound) throw InputError("--images " + source.string() + ": no such file or folder");
    return ReadList(source);  // which refuses a FIFO or a device, naming it
  }
  if (OptionalRegularFile(source / "rgb.txt", "image list")) return ReadList(source / "rgb.txt");
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(source)) {
    // Not only regular files: an image name that is a FIFO is refused when read, not skipped.
    if (!e.is_directory(ec) && IsImage(e.path())) out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  if (out.empty()) throw InputError("--images " + source.string() + ": no rgb.txt and no images in the folder");
  return out;
}

std::vector<cv::Mat> ExtractAll(const std::vector<fs::path>& paths, int features) {
  OrbConfig orb;
  orb.features = features;
  features::OrbExtractor extractor(orb);
  ProgressBar bar(paths.size(), "images");
  const Stopwatch watch;
  std::vector<cv::Mat> out;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    const cv::Mat gray = ReadImageFile(paths[i], "training image", cv::IMREAD_GRAYSCALE, kMaxNamedImageBytes,
                                         kMaxNamedImagePixels);
    std::vector<cv::KeyPoint> keys;
    cv::Mat descriptors;
    extractor.Extract(gray, keys, descriptors);
    out.push_back(descriptors);
    bar.Update(i + 1, static_cast<double>(i + 1) / std::max(1e-3, watch.ElapsedMs() / 1000));
  }
  return out;
}

// --out neither over a list nor among the images it reads, and over an existing
// file only when that is a vocabulary.
void CheckTrainOutput(const VocabArgs& a, const std::vector<fs::path>& images) {
  OutputPlan plan;
  std::set<fs::path> folders;
  for (const std::string& source : a.images) {
    if (fs::is_directory(source)) folders.insert(source);
    else plan.Reads(source, "the image list given with --images");
  }
  for (const fs::path& image : images) folders.insert(image.parent_path());
  for (const fs::path& folder : folders) plan.ReadsFolder(folder, "a folder of the training images");
  plan.Writes(a.out, "--out", std::string(vocab::kFileMagic));
  plan.Check();
}

int RunTrain(const VocabArgs& a) {
  if (a.every < 1) throw InputError("--every must be at least 1, got " + std::to_string(a.every));
  std::vector<fs::path> paths;
  for (const std::string& source : a.images) {
    const std::vector<fs::path> all = ImagesOf(source);
    for (std::size_t i = 0; i < all.size(); i += static_cast<std::size_t>(a.every)) paths.push_back(all[i]);
  }
  CheckTrainOutput(a, paths);
  spdlog::info("vocab: ORB features of {} images", paths.size());
  const std::vector<cv::Mat> descriptors = ExtractAll(paths, a.features);
  std::size_t total = 0;
  for (const cv::Mat& d : descriptors) total += static_cast<std::size_t>(d.rows);
  spdlog::info("vocab: clustering {} descriptors, k {} L {}", total, a.options.branching, a.options.levels);
  const Stopwatch watch;
  std::unique_ptr<ProgressBar> bar;
  const vocab::Vocabulary v = vocab::TrainVocabulary(descriptors, a.options, [&](std::size_t done, std::size_t all) {
    if (!bar) bar = std::make_unique<ProgressBar>(all, "descriptors");
    bar->Update(done, 0);
  });
  bar.reset();
  v.Save(a.out);
  std::printf("vocab: %zu words (%zu nodes, k %d, L %d) from %zu images, %zu descriptors, in %.1f s; wrote %s\n",
              v.size(), v.nodes(), v.branching(), v.levels(), paths.size(), total, watch.ElapsedMs() / 1000,
              a.out.c_str());
  return kExitOk;
}

int RunInfo(const std::string& file) {
  const Stopwatch watch;
  const vocab::Vocabulary v = vocab::Vocabulary::Load(file);
  std::printf("%s: %zu words, %zu nodes, branching %d, levels %d, trained on %llu images, loaded in %.0f ms\n"
              "sha256 %s\n",
              file.c_str(), v.size(), v.nodes(), v.branching(), v.levels(),
              static_cast<unsigned long long>(v.training_images()), watch.ElapsedMs(), v.checksum().c_str());
  return kExitOk;
}

}  // namespace

Action AddVocabCommand(CLI::App& root) {
  auto a = std::make_shared<VocabArgs>();
  CLI::App* cmd = root.add_subcommand("vocab", "Train or inspect the ORB vocabulary of place recognition");
  cmd->require_subcommand(1);
  CLI::App* train = cmd->add_subcommand("train", "Train a vocabulary tree from the ORB features of images");
  train->add_option("--images", a->images, "A folder of images, a TUM folder (its rgb.txt) or a list file; repeatable")
      ->required();
  train->add_option("--out", a->out, "Vocabulary file to write")->required();
  train->add_option("--k", a->options.branching, "Branching factor")->capture_default_str();
  train->add_option("--levels", a->options.levels, "Depth of the tree")->capture_default_str();
  train->add_option("--every", a->every, "Take every N-th image of each source")->capture_default_str();
  train->add_option("--features", a->features, "ORB keypoints per image")->capture_default_str();
  train->add_option("--seed", a->options.seed, "Seed of the clustering")->capture_default_str();
  CLI::App* info = cmd->add_subcommand("info", "Print what a vocabulary file holds and check it");
  info->add_option("file", a->info, "Vocabulary file")->required();
  auto e = std::make_shared<VocabEvalArgs>();
  CLI::App* eval = cmd->add_subcommand("eval", "Place retrieval of a vocabulary on a sequence with ground truth");
  eval->add_option("file", e->vocabulary, "Vocabulary file")->required();
  eval->add_option("--dataset", e->dataset, "TUM-layout folder with groundtruth.txt")->required();
  eval->add_option("--every", e->every, "Take every N-th frame as a view")->capture_default_str();
  eval->add_option("--min-gap", e->min_gap_s, "Seconds a revisited view must be older")->capture_default_str();
  return [a, e, train, eval] {
    if (eval->parsed()) {
      const std::string out = FormatVocabEval(EvaluateVocabulary(*e));
      std::fwrite(out.data(), 1, out.size(), stdout);
      return kExitOk;
    }
    return train->parsed() ? RunTrain(*a) : RunInfo(a->info);
  };
}

}  // namespace sgslam::app
