#include "sgslam/semantic/octomap_builder.h"

#include <fcntl.h>
#include <octomap/ColorOcTree.h>
#include <unistd.h>

#include <cstdio>
#include <sstream>

#include "sgslam/common/error.h"
#include "sgslam/io/atomic_write.h"

namespace sgslam {

namespace {

// The sensor model of the authors' release: a hit and a miss (a free ray) add the
// log-odds of these probabilities, and the clamping bounds keep a voxel's belief
// from growing so strong that new evidence (a person who walked away) cannot turn it.
constexpr double kOctoMapProbHit = 0.7;     // probability
constexpr double kOctoMapProbMiss = 0.4;    // probability
constexpr double kOctoMapClampMin = 0.12;   // probability
constexpr double kOctoMapClampMax = 0.97;   // probability

// Debian's liboctomap is built with debug output on: writing a tree prints "Writing
// N nodes to output stream..." on stderr. Writing happens after every thread has
// stopped, so muting file descriptor 2 for its duration hides nothing else.
class MutedStderr {
 public:
  MutedStderr() {
    std::fflush(stderr);
    saved_ = ::dup(2);
    const int null = ::open("/dev/null", O_WRONLY);
    if (saved_ >= 0 && null >= 0) ::dup2(null, 2);
    if (null >= 0) ::close(null);
  }
  ~MutedStderr() {
    std::fflush(stderr);
    if (saved_ >= 0) {
      ::dup2(saved_, 2);
      ::close(saved_);
    }
  }
  MutedStderr(const MutedStderr&) = delete;
  MutedStderr& operator=(const MutedStderr&) = delete;

 private:
  int saved_ = -1;
};

}  // namespace

OctoMapBuilder::OctoMapBuilder(const SemanticConfig& config)
    : config_(config), tree_(std::make_unique<octomap::ColorOcTree>(config.octomap_resolution)) {
  tree_->setProbHit(kOctoMapProbHit);
  tree_->setProbMiss(kOctoMapProbMiss);
  tree_->setClampingThresMin(kOctoMapClampMin);
  tree_->setClampingThresMax(kOctoMapClampMax);
}

OctoMapBuilder::~OctoMapBuilder() = default;

void OctoMapBuilder::Insert(const std::vector<ColoredPoint>& surface_c, const std::vector<ColoredPoint>& rays_c,
                            const SE3& T_w_c) {
  const Eigen::Vector3d o_w = T_w_c.translation();
  const octomap::point3d origin(static_cast<float>(o_w.x()), static_cast<float>(o_w.y()), static_cast<float>(o_w.z()));
  const auto to_point = [&](const ColoredPoint& c) {
    const Eigen::Vector3d p = T_w_c * c.p.cast<double>();
    return octomap::point3d(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
  };
  // One update per voxel and keyframe, as OctoMap's discretised insertion does: the
  // surface voxels are hits; the voxels the rays cross before them are misses.
  octomap::KeySet occupied, free;
  std::vector<std::pair<octomap::OcTreeKey, Rgb>> colours;
  for (const ColoredPoint& c : surface_c) {
    octomap::OcTreeKey key;
    if (!tree_->coordToKeyChecked(to_point(c), key)) continue;
    if (occupied.insert(key).second) colours.emplace_back(key, c.rgb);
  }
  octomap::KeyRay ray;
  for (const ColoredPoint& c : rays_c) {
    if (!tree_->computeRayKeys(origin, to_point(c), ray)) continue;
    for (const octomap::OcTreeKey& key : ray) free.insert(key);  // the end voxel is not in the ray
  }
  for (const octomap::OcTreeKey& key : free) {
    if (!occupied.count(key)) tree_->updateNode(key, false, /*lazy_eval=*/true);
  }
  for (const octomap::OcTreeKey& key : occupied) tree_->updateNode(key, true, /*lazy_eval=*/true);
  for (const auto& [key, c] : colours) tree_->integrateNodeColor(key, c[0], c[1], c[2]);
  dirty_ = true;
}

void OctoMapBuilder::Clear() {
  tree_->clear();
  dirty_ = false;
}

void OctoMapBuilder::Finalize() {
  // ColorOcTree::updateInnerOccupancy (OctoMap 1.9) dereferences the root without
  // checking it: a tree that every insert left empty (no depth in range) has none.
  if (!dirty_ || tree_->getRoot() == nullptr) {
    dirty_ = false;
    return;
  }
  tree_->updateInnerOccupancy();
  tree_->prune();  // merges uniform (mostly free) regions: memory proportional to surfaces
  dirty_ = false;
}

bool OctoMapBuilder::IsFree(const Eigen::Vector3d& p_w) const {
  const octomap::ColorOcTreeNode* node =
      tree_->search(static_cast<double>(p_w.x()), static_cast<double>(p_w.y()), static_cast<double>(p_w.z()));
  return node != nullptr && !tree_->isNodeOccupied(node);
}

bool OctoMapBuilder::IsOccupied(const Eigen::Vector3d& p_w) const {
  const octomap::ColorOcTreeNode* node =
      tree_->search(static_cast<double>(p_w.x()), static_cast<double>(p_w.y()), static_cast<double>(p_w.z()));
  return node != nullptr && tree_->isNodeOccupied(node);
}

double OctoMapBuilder::resolution() const { return tree_->getResolution(); }

std::size_t OctoMapBuilder::OccupiedLeaves() const {
  std::size_t n = 0;
  for (auto it = tree_->begin_leafs(), end = tree_->end_leafs(); it != end; ++it) {
    if (tree_->isNodeOccupied(*it)) ++n;
  }
  return n;
}

std::vector<Eigen::Vector4f> OctoMapBuilder::OccupiedCells() const {
  std::vector<Eigen::Vector4f> out;
  for (auto it = tree_->begin_leafs(), end = tree_->end_leafs(); it != end; ++it) {
    if (!tree_->isNodeOccupied(*it)) continue;
    const octomap::point3d c = it.getCoordinate();
    out.emplace_back(c.x(), c.y(), c.z(), static_cast<float>(it.getSize()));
  }
  return out;
}

void OctoMapBuilder::Write(const std::filesystem::path& path) {
  Finalize();
  std::ostringstream bytes(std::ios::binary);
  bool ok = false;
  {
    const MutedStderr quiet;
    ok = tree_->writeBinaryConst(bytes);
  }
  if (!ok) throw InputError("cannot write the OctoMap to " + path.string());
  WriteFileAtomically(path, bytes.str());
}

}  // namespace sgslam
