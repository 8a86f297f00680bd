#include "render/accel/bvh.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>
#include <vector>

#include "core/profiler.h"
#include "render/accel/centre_region.h"

namespace rt {
namespace {

constexpr int kBins = 16;
constexpr float kInf = std::numeric_limits<float>::infinity();
// Ranges at least this long are binned in chunks on several threads.
constexpr std::uint32_t kParallelBinning = 1u << 16;
constexpr std::uint32_t kBinningChunk = 1u << 14;
// Ranges shorter than this are built by one task, into a block of their own.
constexpr std::uint32_t kSerialSubtree = 1u << 12;

// Four floats in one register (a GCC and Clang vector extension, on x86-64
// and AArch64 alike): x, y, z and a spare lane. Lane-wise + - * / round as
// the scalar operations do.
using Float4 = float __attribute__((vector_size(16)));
using Int4 = std::int32_t __attribute__((vector_size(16)));

inline Float4 splat(float v) { return Float4{v, v, v, v}; }
// Lane-wise min and max that keep the first argument on a tie, as glm::min
// and glm::max do. A sphere's box (finite, radius > 0) never holds -0, so
// the bounds of a set of boxes are the same bits in whatever order the set
// is grown, in one pass or in chunks. Centres may hold -0, and the centroid
// bounds then a zero of either sign; a centre's bin cannot tell which (c -
// lo and the extent keep their values).
inline Float4 min4(Float4 a, Float4 b) { return b < a ? b : a; }
inline Float4 max4(Float4 a, Float4 b) { return a < b ? b : a; }

struct Box {
  Float4 lo = splat(kInf);
  Float4 hi = splat(-kInf);

  void grow(const Box& b) {
    lo = min4(lo, b.lo);
    hi = max4(hi, b.hi);
  }
  [[nodiscard]] float halfArea() const {
    if (lo[0] > hi[0]) return 0.0f;
    const Float4 e = hi - lo;
    return e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
  }
  [[nodiscard]] glm::vec3 low() const { return {lo[0], lo[1], lo[2]}; }
  [[nodiscard]] glm::vec3 high() const { return {hi[0], hi[1], hi[2]}; }
};

// One sphere as the build reads it: centre and radius, scene index, and its
// bin on each axis in the last binning, side by side and moved as a whole
// by the partitions (no indirection through Bvh::order).
struct Prim {
  std::array<float, 4> centreRadius;  // x, y, z, r
  std::uint32_t index;
  std::array<std::uint8_t, 4> bin;  // x, y, z, unused

  [[nodiscard]] Float4 load() const {
    Float4 v;
    std::memcpy(&v, centreRadius.data(), sizeof v);
    return v;
  }
};
static_assert(sizeof(Prim) == 24);

// A node's spheres: their bounds and their centres' bounds.
struct Range {
  std::uint32_t begin = 0, end = 0;
  Box bounds, centroids;
  [[nodiscard]] std::uint32_t count() const { return end - begin; }
};

// The bins of a centre on the three axes of a node's centroid bounds, as
// static_cast<int>(kBins * (c - lo) / extent) clamped to [0, kBins - 1]:
// the division (not a reciprocal multiply) decides the bins. An axis that
// cannot be split (no extent) puts every centre in bin 0; the spare lane
// (the radius) lands in bin 0 too.
struct Binner {
  Float4 lo, extent;
  std::array<bool, 3> splittable{};

  explicit Binner(const Box& centroids) : lo(centroids.lo), extent(centroids.hi - centroids.lo) {
    for (int a = 0; a < 3; ++a) {
      splittable[a] = centroids.hi[a] > centroids.lo[a];
      if (!splittable[a]) extent[a] = 1.0f;
    }
    lo[3] = 0.0f;
    extent[3] = kInf;
  }
  [[nodiscard]] Int4 operator()(Float4 centre) const {
    const Int4 b = __builtin_convertvector(splat(static_cast<float>(kBins)) * (centre - lo) / extent, Int4);
    const Int4 zero{0, 0, 0, 0}, last{kBins - 1, kBins - 1, kBins - 1, kBins - 1};
    const Int4 low = b < zero ? zero : b;
    return low > last ? last : low;
  }
};

struct Bin {
  Box bounds;
  std::uint32_t count = 0;
};
using AxisBins = std::array<Bin, kBins>;

// The three axes' bins of a range, filled in one pass over it, which also
// records each sphere's bins for the partition.
struct Binning {
  std::array<AxisBins, 3> axes{};

  void add(std::span<Prim> prims, const Binner& binner) {
    for (Prim& p : prims) {
      const Float4 cr = p.load();
      const Float4 r = splat(cr[3]);
      const Box box{cr - r, cr + r};
      const Int4 b = binner(cr);
      for (int a = 0; a < 3; ++a) {
        p.bin[a] = static_cast<std::uint8_t>(b[a]);
        Bin& bin = axes[a][static_cast<std::size_t>(b[a])];
        bin.bounds.grow(box);
        ++bin.count;
      }
    }
  }
  void merge(const Binning& other) {
    for (int a = 0; a < 3; ++a) {
      for (std::size_t b = 0; b < kBins; ++b) {
        axes[a][b].bounds.grow(other.axes[a][b].bounds);
        axes[a][b].count += other.axes[a][b].count;
      }
    }
  }
};

struct Split {
  int axis = -1;
  int bin = 0;  // spheres in bins [0, bin] go left
  float cost = kInf;
};

// SAH cost (in units of sphere tests, relative to the parent's area) of
// each plane between bins, from prefix and suffix sweeps; the first
// cheapest plane wins, axes in order x, y, z. Only the planes just above a
// non-empty bin are priced: a plane above an empty bin splits the spheres
// as the plane below it does, at the same cost, so it never wins.
void considerSplits(const AxisBins& bins, int axis, Split& best) {
  std::array<std::size_t, kBins> used{};
  std::size_t n = 0;
  for (std::size_t b = 0; b < kBins; ++b) {
    if (bins[b].count != 0) used[n++] = b;
  }
  if (n < 2) return;
  // rightCost[k]: the spheres in used bins k.. n-1 (those above plane used[k - 1]).
  std::array<float, kBins> rightCost{};
  Box right;
  std::uint32_t rightCount = 0;
  for (std::size_t k = n - 1; k > 0; --k) {
    right.grow(bins[used[k]].bounds);
    rightCount += bins[used[k]].count;
    rightCost[k] = right.halfArea() * static_cast<float>(rightCount);
  }
  Box left, all = right;
  all.grow(bins[used[0]].bounds);
  std::uint32_t leftCount = 0;
  const float parentArea = std::max(all.halfArea(), std::numeric_limits<float>::min());
  for (std::size_t k = 0; k + 1 < n; ++k) {
    left.grow(bins[used[k]].bounds);
    leftCount += bins[used[k]].count;
    if (rightCost[k + 1] == 0.0f) continue;
    const float cost = 1.0f + (left.halfArea() * static_cast<float>(leftCount) + rightCost[k + 1]) / parentArea;
    if (cost < best.cost) best = {axis, static_cast<int>(used[k]), cost};
  }
}

// A built subtree waiting for its place in Bvh::nodes. The nodes are laid
// out depth first with a node's two children side by side, allocated when
// the node is split: below a node come its children's pair, then the left
// child's descendants, then the right child's. A subtree built by one task
// holds that layout in `block` (its root at 0, indices relative to it); a
// subtree split in parallel holds its two children as pieces.
struct Piece {
  BvhNode root{};
  std::vector<BvhNode> block;
  std::unique_ptr<Piece> left, right;
  std::size_t descendants = 0;  // nodes below the root
  int depth = 0;                // deepest level in the subtree, counted from the tree's root
};

class Builder {
 public:
  Builder(std::span<const Sphere> spheres, BvhLeafRule leaves) : leaves_(leaves), prims_(spheres.size()) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, spheres.size(), kBinningChunk), [&](const auto& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i) {
        const Sphere& s = spheres[i];
        prims_[i] = {{s.position.x, s.position.y, s.position.z, s.radius}, static_cast<std::uint32_t>(i), {}};
      }
    });
  }

  Bvh build() && {
    Bvh bvh;
    Range all = measure(bvh);
    const std::unique_ptr<Piece> top = buildPiece(all, 0);
    bvh.depth = top->depth;
    // The spheres go before the nodes come, and each block as soon as it
    // is placed, so that the peak holds little more than the finished tree.
    bvh.order.resize(prims_.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, prims_.size(), kBinningChunk), [&](const auto& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i) bvh.order[i] = prims_[i].index;
    });
    prims_ = std::vector<Prim>();  // (= {} would keep the capacity)
    bvh.nodes.resize(1 + top->descendants);
    place(*top, 0, 1, bvh.nodes);
    return bvh;
  }

 private:
  // The root's range, and the largest radius and |coordinate| (traversalPad()).
  Range measure(Bvh& bvh) {
    struct Extent {
      Box bounds, centroids;
      float maxRadius = 0.0f;
    };
    const std::vector<Extent> chunks = inChunks(0, count(), Extent{}, [&](std::span<Prim> prims, Extent& e) {
      for (const Prim& p : prims) {
        const Float4 cr = p.load();
        const Float4 r = splat(cr[3]);
        e.bounds.grow({cr - r, cr + r});
        e.centroids.grow({cr, cr});
        e.maxRadius = std::max(e.maxRadius, cr[3]);
      }
    });
    Range all{0, count(), {}, {}};
    for (const Extent& e : chunks) {
      all.bounds.grow(e.bounds);
      all.centroids.grow(e.centroids);
      bvh.maxRadius = std::max(bvh.maxRadius, e.maxRadius);
    }
    for (int a = 0; a < 3; ++a) {
      bvh.maxCoordinate = std::max({bvh.maxCoordinate, std::abs(all.bounds.lo[a]), std::abs(all.bounds.hi[a])});
    }
    return all;
  }

  [[nodiscard]] std::uint32_t count() const { return static_cast<std::uint32_t>(prims_.size()); }

  // `work` run over consecutive chunks of [begin, end) on the pool, one
  // result per chunk (starting as `init`) in range order.
  template <typename Result, typename Work>
  std::vector<Result> inChunks(std::uint32_t begin, std::uint32_t end, const Result& init, Work work) {
    const std::uint32_t chunks = (end - begin + kBinningChunk - 1) / kBinningChunk;
    std::vector<Result> results(chunks, init);
    tbb::parallel_for(std::uint32_t{0}, chunks, [&](std::uint32_t k) {
      const std::uint32_t first = begin + k * kBinningChunk;
      work(std::span(prims_).subspan(first, std::min(kBinningChunk, end - first)), results[k]);
    });
    return results;
  }

  // The range's bins, in chunks on the pool when it is long: min, max and
  // counts, merged in range order, give the same bins as one pass.
  [[nodiscard]] Binning bin(const Range& range, const Binner& binner) {
    Binning binning;
    if (range.count() < kParallelBinning) {
      binning.add(std::span(prims_).subspan(range.begin, range.count()), binner);
      return binning;
    }
    const auto parts =
        inChunks(range.begin, range.end, binning, [&](std::span<Prim> prims, Binning& b) { b.add(prims, binner); });
    for (const Binning& part : parts) binning.merge(part);
    return binning;
  }

  // Splits `range` in place into its two children, or returns false when it
  // stays a leaf (few spheres, the depth limit, or a leaf is cheaper).
  bool split(const Range& range, int depth, int& axis, Range& left, Range& right) {
    if (range.count() <= leaves_.always || depth >= kBvhMaxDepth) return false;
    const Binner binner(range.centroids);
    const Binning binning = bin(range, binner);
    Split best;
    for (int a = 0; a < 3; ++a) {
      if (binner.splittable[a]) considerSplits(binning.axes[a], a, best);
    }
    // A leaf costs one test per sphere; an inner node one box test more.
    if (best.axis < 0 || (range.count() <= leaves_.sahUpTo && best.cost >= static_cast<float>(range.count()))) {
      return false;
    }
    const AxisBins& bins = binning.axes[best.axis];
    left = {range.begin, range.begin, {}, {}};
    right = {range.begin, range.end, {}, {}};
    for (std::size_t b = 0; b < kBins; ++b) {
      Range& side = static_cast<int>(b) <= best.bin ? left : right;
      side.bounds.grow(bins[b].bounds);
      if (&side == &left) left.end += bins[b].count;
    }
    right.begin = left.end;
    const auto first = prims_.begin() + range.begin;
    const auto axisIndex = static_cast<std::size_t>(best.axis);
    // std::partition, as the builder always used, so that Bvh::order keeps
    // its order within leaves. It asks the predicate exactly once per
    // sphere, which grows that side's centroid bounds on the way.
    Box leftCentroids, rightCentroids;
    std::partition(first, first + range.count(), [&](const Prim& p) {
      const bool goesLeft = p.bin[axisIndex] <= best.bin;
      const Float4 c = p.load();
      if (goesLeft) {
        leftCentroids.grow({c, c});
      } else {
        rightCentroids.grow({c, c});
      }
      return goesLeft;
    });
    left.centroids = leftCentroids;
    right.centroids = rightCentroids;
    axis = best.axis;
    return left.count() > 0 && right.count() > 0;
  }

  static BvhNode leafNode(const Range& range) {
    if (range.count() > BvhNode::kCountMask) throw std::length_error("BVH leaf too large");
    return {range.bounds.low(), range.begin, range.bounds.high(), range.count()};
  }

  static BvhNode innerNode(const Range& range, int axis, std::uint32_t left) {
    return {range.bounds.low(), left, range.bounds.high(), static_cast<std::uint32_t>(axis) << 30};
  }

  std::unique_ptr<Piece> buildPiece(const Range& range, int depth) {
    auto piece = std::make_unique<Piece>();
    piece->depth = depth;
    if (range.count() < kSerialSubtree) {
      piece->block.reserve(2 * std::size_t{range.count()} - 1);  // a binary tree over them, at most
      piece->block.emplace_back();
      buildSerial(range, depth, 0, *piece);
      piece->root = piece->block[0];
      piece->descendants = piece->block.size() - 1;
      return piece;
    }
    int axis = 0;
    Range left, right;
    if (!split(range, depth, axis, left, right)) {
      piece->root = leafNode(range);
      return piece;
    }
    piece->root = innerNode(range, axis, 0);
    tbb::parallel_invoke([&] { piece->left = buildPiece(left, depth + 1); },
                         [&] { piece->right = buildPiece(right, depth + 1); });
    piece->descendants = 2 + piece->left->descendants + piece->right->descendants;
    piece->depth = std::max(piece->left->depth, piece->right->depth);
    return piece;
  }

  void buildSerial(const Range& range, int depth, std::size_t node, Piece& piece) {
    piece.depth = std::max(piece.depth, depth);
    int axis = 0;
    Range left, right;
    if (!split(range, depth, axis, left, right)) {
      piece.block[node] = leafNode(range);
      return;
    }
    const auto child = static_cast<std::uint32_t>(piece.block.size());
    piece.block[node] = innerNode(range, axis, child);
    piece.block.emplace_back();
    piece.block.emplace_back();
    buildSerial(left, depth + 1, child, piece);
    buildSerial(right, depth + 1, child + 1, piece);
  }

  // Writes `piece` with its root at nodes[at] and its descendants from nodes[below].
  static void place(Piece& piece, std::size_t at, std::size_t below, std::vector<BvhNode>& nodes) {
    BvhNode root = piece.root;
    if (!root.leaf()) root.first = static_cast<std::uint32_t>(below);
    nodes[at] = root;
    if (piece.left) {
      const std::size_t afterPair = below + 2;
      tbb::parallel_invoke([&] { place(*piece.left, below, afterPair, nodes); },
                           [&] { place(*piece.right, below + 1, afterPair + piece.left->descendants, nodes); });
      return;
    }
    const std::size_t shift = below - 1;  // block index k > 0 goes to nodes[k + shift]
    for (std::size_t k = 1; k < piece.block.size(); ++k) {
      BvhNode n = piece.block[k];
      if (!n.leaf()) n.first += static_cast<std::uint32_t>(shift);
      nodes[k + shift] = n;
    }
    piece.block = std::vector<BvhNode>();
  }

  BvhLeafRule leaves_;
  std::vector<Prim> prims_;
};

}  // namespace

namespace {

// What each node's spheres give the pad: their largest radius and the
// largest |coordinate| of the node's box (docs/render-model.md section 3,
// "The traversal pad"). Children come after their parent, so one pass from
// the back sees every child before its parent.
struct NodeExtent {
  double radius = 0.0;
  double coordinate = 0.0;
};

std::vector<NodeExtent> nodeExtents(const Bvh& bvh, std::span<const Sphere> spheres) {
  std::vector<NodeExtent> extents(bvh.nodes.size());
  for (std::size_t i = bvh.nodes.size(); i-- > 0;) {
    const BvhNode& n = bvh.nodes[i];
    NodeExtent& e = extents[i];
    for (int a = 0; a < 3; ++a) {
      e.coordinate = std::max({e.coordinate, double(std::abs(n.lo[a])), double(std::abs(n.hi[a]))});
    }
    if (n.leaf()) {
      for (std::uint32_t k = n.first; k < n.first + n.count(); ++k) {
        e.radius = std::max(e.radius, double(spheres[bvh.order[k]].radius));
      }
    } else {
      e.radius = std::max(extents[n.first].radius, extents[n.first + 1].radius);
    }
  }
  return extents;
}

// The part of the pad a node's own spheres give under local padding: the
// scene formula's terms in the box's radius R and |coordinate| C, with its
// tangency term sqrt(R (o + C)) split as sqrt(R C) + sqrt(R o) and
// sqrt(R o) <= (SPLIT R + o / SPLIT) / 2, so that what is left for the ray
// is linear in its origin o (localOriginSlope()).
double localBoxPad(const NodeExtent& e) {
  return RT_BVH_PAD_SCALE * e.coordinate + RT_BVH_PAD_TANGENT * std::sqrt(e.radius * e.coordinate) +
         RT_BVH_PAD_TANGENT * RT_BVH_PAD_SPLIT * e.radius / 2 + RT_BVH_PAD_RADIUS * e.radius;
}

// The ray's share of the split tangency term, T / (2 SPLIT) per unit of the
// origin's |coordinate|, rounded up to a float.
float localOriginSlope() {
  const double slope = RT_BVH_PAD_TANGENT / (2 * RT_BVH_PAD_SPLIT);
  const auto rounded = static_cast<float>(slope);
  return double(rounded) < slope ? std::nextafter(rounded, kInf) : rounded;
}

// A box is widened by twice its spheres' part: the first covers the pad in
// space, the second the same pad along the ray (a box widened by w is
// entered at least w earlier and left at least w later by a ray of unit
// direction, each |1 / direction component| being at least 1). 2^-10 more
// covers the direction's rounding and the slab test's.
float widenedDown(float bound, double by) {
  const double exact = double(bound) - by;
  const auto rounded = static_cast<float>(exact);
  return double(rounded) > exact ? std::nextafter(rounded, -kInf) : rounded;
}

float widenedUp(float bound, double by) {
  const double exact = double(bound) + by;
  const auto rounded = static_cast<float>(exact);
  return double(rounded) < exact ? std::nextafter(rounded, kInf) : rounded;
}

void padBoxesLocally(Bvh& bvh, std::span<const NodeExtent> extents) {
  for (std::size_t i = 0; i < bvh.nodes.size(); ++i) {
    const double by = 2 * localBoxPad(extents[i]) * (1 + 0x1p-10);
    BvhNode& n = bvh.nodes[i];
    for (int a = 0; a < 3; ++a) {
      n.lo[a] = widenedDown(n.lo[a], by);
      n.hi[a] = widenedUp(n.hi[a], by);
    }
  }
  bvh.padding = BoxPadding::local;
  bvh.pad = {0.0f, 0.0f, localOriginSlope()};
}

// The |coordinate| a typical ray starts from: the median over the spheres
// of their centre's largest |coordinate|.
float typicalOrigin(std::span<const Sphere> spheres) {
  std::vector<float> coordinates(spheres.size());
  std::ranges::transform(spheres, coordinates.begin(), [](const Sphere& s) {
    return std::max({std::abs(s.position.x), std::abs(s.position.y), std::abs(s.position.z)});
  });
  const auto middle = coordinates.begin() + static_cast<std::ptrdiff_t>(coordinates.size() / 2);
  std::ranges::nth_element(coordinates, middle);
  return *middle;
}

double surfaceArea(glm::vec3 lo, glm::vec3 hi, double widenedBy) {
  const double x = double(hi.x) - double(lo.x) + 2 * widenedBy;
  const double y = double(hi.y) - double(lo.y) + 2 * widenedBy;
  const double z = double(hi.z) - double(lo.z) + 2 * widenedBy;
  return 2 * (x * y + y * z + z * x);
}

double surfaceArea(const BvhNode& n, double widenedBy) { return surfaceArea(n.lo, n.hi, widenedBy); }

// What padPrice() reads of the spheres, taken once for both paddings.
struct PriceInputs {
  float origin;   // typicalOrigin()
  double region;  // the surface area of typicalCentreRegion(), or of the root's box where that is flat
};

PriceInputs priceInputs(const Bvh& bvh, std::span<const Sphere> spheres) {
  // Where a scene's rays mostly go: one huge sphere does not stand for
  // the scene the way the root's box would (render/accel/centre_region.h).
  const CentreRegion typical = typicalCentreRegion(spheres);
  double region = surfaceArea(typical.lo, typical.hi, 0.0);
  if (!(region > 0.0)) region = surfaceArea(bvh.nodes[0], 0.0);
  return {typicalOrigin(spheres), region};
}

// padPrice() on the tight boxes: the surface-area heuristic with each box's
// chance of being reached taken against the typical region (and at most 1),
// a visit costing one and a leaf's spheres one each.
double padPriceOfTightTree(const Bvh& bvh, std::span<const NodeExtent> extents, const PriceInputs& in,
                           BoxPadding padding) {
  const double sceneShare = traversalPad(bvh.maxRadius, bvh.maxCoordinate, in.origin);
  const double rayShare = RT_BVH_PAD_SCALE * in.origin + RT_BVH_PAD_MIN + double(localOriginSlope()) * in.origin;
  const auto widening = [&](std::size_t i) {
    return padding == BoxPadding::scene ? sceneShare : 2 * localBoxPad(extents[i]) + rayShare;
  };
  double price = 0.0;
  for (std::size_t i = 0; i < bvh.nodes.size(); ++i) {
    const BvhNode& n = bvh.nodes[i];
    const double reached = std::min(1.0, surfaceArea(n, widening(i)) / in.region);
    price += reached * (n.leaf() ? double(n.count()) + 1.0 : 1.0);
  }
  return price;
}

}  // namespace

double padPrice(const Bvh& bvh, std::span<const Sphere> spheres, BoxPadding padding) {
  if (bvh.padding != BoxPadding::scene) throw std::invalid_argument("padPrice needs the tree's tight boxes");
  return padPriceOfTightTree(bvh, nodeExtents(bvh, spheres), priceInputs(bvh, spheres), padding);
}

Bvh buildBvh(std::span<const Sphere> spheres, BvhLeafRule leaves, std::optional<BoxPadding> padding) {
  ZoneScopedN("BVH build");
  if (spheres.empty()) throw std::invalid_argument("a BVH needs at least one sphere");
  if (leaves.always == 0 || leaves.sahUpTo < leaves.always) {
    throw std::invalid_argument("a BVH leaf rule needs 1 <= always <= sahUpTo");
  }
  const auto start = std::chrono::steady_clock::now();
  Bvh bvh = Builder(spheres, leaves).build();
  bvh.pad = {bvh.maxRadius, bvh.maxCoordinate, 0.0f};
  const std::vector<NodeExtent> extents = nodeExtents(bvh, spheres);
  const PriceInputs inputs = priceInputs(bvh, spheres);
  const double scenePrice = padPriceOfTightTree(bvh, extents, inputs, BoxPadding::scene);
  const double localPrice = padPriceOfTightTree(bvh, extents, inputs, BoxPadding::local);
  // Local padding only where it saves a tenth: where the two are close
  // (uniform sizes) the scene's pad keeps the boxes as they always were.
  const BoxPadding chosen = padding.value_or(localPrice < 0.9 * scenePrice ? BoxPadding::local : BoxPadding::scene);
  bvh.price = chosen == BoxPadding::local ? localPrice : scenePrice;
  if (chosen == BoxPadding::local) padBoxesLocally(bvh, extents);
  bvh.buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return bvh;
}

}  // namespace rt
