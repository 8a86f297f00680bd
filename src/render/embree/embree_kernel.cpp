#include "render/embree/embree_kernel.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

#include "render/scalar/scalar_span.h"

namespace rt {
namespace {

using embree::FrameData;
using embree::Lane;
using embree::Slot;
using kernel::PathSegment;
using kernel::RaycastHit;
using kernel::Vec3;

std::string errorName(RTCError error) {
  switch (error) {
    case RTC_ERROR_NONE: return "no error";
    case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
    case RTC_ERROR_CANCELLED: return "cancelled";
    default: return "unknown error";
  }
}

// Embree reports errors through the device, not by exceptions; a failed
// build must not go on to be traced.
void throwOnDeviceError(RTCDevice device, const char* what) {
  const RTCError error = rtcGetDeviceError(device);
  if (error != RTC_ERROR_NONE) throw std::runtime_error(std::string("Embree: ") + what + ": " + errorName(error));
}

// No configuration string: Embree picks the best instruction set it was
// built with for this CPU, as a user's default device would. The device
// must offer what the scene and the model need: sphere points (a build
// option, EMBREE_GEOMETRY_POINT) and, for rays that start inside a sphere,
// its far hit (no EMBREE_BACKFACE_CULLING_SPHERES).
embree::DeviceHandle newDevice() {
  RTCDevice device = rtcNewDevice(nullptr);
  if (device == nullptr) {
    throw RendererUnavailable("renderer 'embree': Embree has no device on this machine (" +
                              errorName(rtcGetDeviceError(nullptr)) + ")");
  }
  embree::DeviceHandle handle(device);
  if (rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_POINT_GEOMETRY_SUPPORTED) == 0) {
    throw RendererUnavailable("renderer 'embree': this Embree was built without point geometry (sphere points)");
  }
  if (embree::api::cullsSphereBackFaces(device)) {
    throw RendererUnavailable(
        "renderer 'embree': this Embree culls the back faces of spheres (EMBREE_BACKFACE_CULLING_SPHERES), "
        "so a ray that starts inside a sphere would miss it");
  }
  return handle;
}

int nativePacketWidth(RTCDevice device) {
  if (rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED) != 0) return 16;
  if (rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED) != 0) return 8;
  if (rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED) != 0) return 4;
  throw RendererUnavailable("renderer 'embree': this Embree was built without ray packets");
}

int packetWidth(RTCDevice device, int lanes) {
  if (lanes == ParallelSettings::kNativeLanes) return nativePacketWidth(device);
  if (lanes == 4 || lanes == 8 || lanes == 16) return lanes;
  throw std::invalid_argument("renderer 'embree': lanes " + std::to_string(lanes) +
                              " is not an Embree packet width (4, 8 or 16)");
}

// Embree's packet type of each width (the trace call is api::intersect).
template <int W>
struct Packet;
template <>
struct Packet<4> {
  static RTCRayHit4& of(Slot& s) { return s.packet4; }
};
template <>
struct Packet<8> {
  static RTCRayHit8& of(Slot& s) { return s.packet8; }
};
template <>
struct Packet<16> {
  static RTCRayHit16& of(Slot& s) { return s.packet16; }
};

// Loads the live lanes' rays into the packet and asks Embree for each one's
// nearest hit beyond EPS (docs/render-model.md section 3's minimum
// distance). Every lane is written, the masked ones too, so Embree never
// reads stale values.
template <int W>
void tracePacket(const FrameData& f, Slot& s, embree::api::Coherence coherence) {
  auto& p = Packet<W>::of(s);
  for (int i = 0; i < W; ++i) {
    const Lane& lane = s.lanes[static_cast<std::size_t>(i)];
    s.valid[static_cast<std::size_t>(i)] = lane.live ? -1 : 0;
    p.ray.org_x[i] = lane.ray.origin.x;
    p.ray.org_y[i] = lane.ray.origin.y;
    p.ray.org_z[i] = lane.ray.origin.z;
    p.ray.dir_x[i] = lane.ray.direction.x;
    p.ray.dir_y[i] = lane.ray.direction.y;
    p.ray.dir_z[i] = lane.ray.direction.z;
    p.ray.tnear[i] = kernel::kEpsilon<float>;
    p.ray.tfar[i] = std::numeric_limits<float>::infinity();
    p.ray.time[i] = 0.0f;
    p.ray.mask[i] = ~0u;
    p.ray.id[i] = static_cast<unsigned>(i);
    p.ray.flags[i] = 0;
    embree::api::clearHit(p.hit, i);
  }
  embree::api::QueryArguments args = embree::api::queryArguments(coherence);
  embree::api::intersect(s.valid.data(), f.scene, args, p);
}

// Lane i's hit as our model records it: Embree gives the distance (tfar)
// and the sphere (primID: the one geometry's primitives are the scene's
// spheres in order); position and normal (facing the ray) are computed from them as
// section 3 does, not taken from Embree's unnormalised Ng.
template <int W>
RaycastHit<float> hitOf(const FrameData& f, Slot& s, int i) {
  const auto& p = Packet<W>::of(s);
  const int sphere = p.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID ? -1 : static_cast<int>(p.hit.primID[i]);
  return kernel::hitRecord(s.lanes[static_cast<std::size_t>(i)].ray, f.inputs.spheres, p.ray.tfar[i], sphere);
}

bool anyLive(const Slot& s) {
  return std::ranges::any_of(s.lanes, [](const Lane& lane) { return lane.live; });
}

Vec3<float> colorOf(const FrameData& f, int sphere) {
  return Vec3<float>(f.inputs.spheres[static_cast<std::size_t>(sphere)].color);
}

// Primary rays for pixels x..x+count-1 of row y (section 2). Lanes past
// `count` repeat the last pixel but are not live, so a span's tail packet
// traces only its own pixels.
template <int W>
void startPacket(const FrameData& f, Slot& s, int y, int x, int count) {
  const Extent extent = f.image->extent();
  for (int i = 0; i < W; ++i) {
    Lane& lane = s.lanes[static_cast<std::size_t>(i)];
    const int px = x + std::min(i, count - 1);
    lane.ray = kernel::primaryRay<float>(f.camera, extent, px, y);
    lane.color = Vec3<float>(0);
    lane.throughput = Vec3<float>(1);
    lane.segments = 0;
    lane.live = i < count;
  }
}

// Traces the packet depth by depth, up to maxDepth (with the bounce exit,
// until no lane is live), and hands each live lane to visit(depth, i, lane).
template <int W, bool kBounceExit, typename Visit>
void forEachDepth(const FrameData& f, Slot& s, const Visit& visit) {
  for (int depth = 0; depth < f.inputs.maxDepth; ++depth) {
    if (kBounceExit && !anyLive(s)) break;
    tracePacket<W>(f, s, depth == 0 ? embree::api::Coherence::coherent : embree::api::Coherence::incoherent);
    for (int i = 0; i < W; ++i) {
      Lane& lane = s.lanes[static_cast<std::size_t>(i)];
      if (lane.live) visit(depth, i, lane);
    }
  }
}

// Section 5's single-pass loop, per lane, as kernel::traceSinglePass does
// it with Embree's hits. Without the bounce exit a lane that missed stays
// in the packet and is traced again with zero throughput (it misses again,
// adding exactly 0), as the scalar kernel's dead ray does.
template <int W, bool kBounceExit>
void traceSinglePass(const FrameData& f, Slot& s) {
  const kernel::ShadingInputs<float>& in = f.inputs;
  forEachDepth<W, kBounceExit>(f, s, [&](int /*depth*/, int i, Lane& lane) {
    const RaycastHit<float> hit = hitOf<W>(f, s, i);
    if (!hit.hit()) {
      lane.color += lane.throughput * in.background;
      if constexpr (kBounceExit) {
        lane.live = false;
      } else {
        lane.throughput = Vec3<float>(0);
      }
      return;
    }
    kernel::shadeBounce(in, hit, lane.ray, lane.color, lane.throughput);
  });
}

// Section 5's backward pass over lane i's stored segments, the same fold
// as kernel::traceTwoPass.
template <int W>
Vec3<float> foldSegments(const kernel::ShadingInputs<float>& in, std::span<const PathSegment<float>> segments, int i,
                         int count) {
  Vec3<float> acc(0);
  for (int d = count - 1; d >= 0; --d) {
    acc = kernel::foldSegment(in, acc, segments[static_cast<std::size_t>(d * W + i)]);
  }
  return acc;
}

// Section 5's two-pass algorithm: the forward pass traces the packet depth
// by depth and stores every lane's ray, hit and sphere colour; after a miss
// a lane's ray stays as it is (traced again, missing again, unless the
// bounce exit drops the lane); then each lane is folded backwards.
template <int W, bool kBounceExit>
void traceTwoPass(const FrameData& f, Slot& s, std::span<PathSegment<float>> segments) {
  const kernel::ShadingInputs<float>& in = f.inputs;
  forEachDepth<W, kBounceExit>(f, s, [&](int depth, int i, Lane& lane) {
    PathSegment<float>& seg = segments[static_cast<std::size_t>(depth * W + i)];
    seg.ray = lane.ray;
    seg.hit = hitOf<W>(f, s, i);
    lane.segments = depth + 1;
    if (!seg.hit.hit()) {
      if constexpr (kBounceExit) lane.live = false;
      return;
    }
    seg.sphereColor = colorOf(f, seg.hit.sphere);
    lane.ray = kernel::reflectedRay(lane.ray, seg.hit);
  });
  for (int i = 0; i < W; ++i) {
    Lane& lane = s.lanes[static_cast<std::size_t>(i)];
    lane.color = foldSegments<W>(in, segments, i, lane.segments);
  }
}

// The span level: packets of W adjacent pixels from x0 (a multiple of W
// for tiles, 0 for rows), the last one partly masked.
template <int W, Algorithm kAlgorithm, bool kBounceExit>
void renderPacketSpan(const FrameData& f, Slot& s, std::span<PathSegment<float>> segments, int y, int x0, int x1) {
  const std::span<Rgba8> row = f.image->row(y);
  for (int x = x0; x < x1; x += W) {
    const int count = std::min(W, x1 - x);
    startPacket<W>(f, s, y, x, count);
    if constexpr (kAlgorithm == Algorithm::two_pass) {
      traceTwoPass<W, kBounceExit>(f, s, segments);
    } else {
      traceSinglePass<W, kBounceExit>(f, s);
    }
    for (int i = 0; i < count; ++i) {
      row[static_cast<std::size_t>(x + i)] = kernel::toRgba8(s.lanes[static_cast<std::size_t>(i)].color);
    }
  }
}

template <Algorithm kAlgorithm, bool kBounceExit>
embree::SpanFunction spanFor(int width) {
  switch (width) {
    case 4: return &renderPacketSpan<4, kAlgorithm, kBounceExit>;
    case 8: return &renderPacketSpan<8, kAlgorithm, kBounceExit>;
    case 16: return &renderPacketSpan<16, kAlgorithm, kBounceExit>;
    default: throw std::logic_error("renderer 'embree': no span function for this packet width");
  }
}

}  // namespace

EmbreeKernel::EmbreeKernel(const ParallelSettings& settings)
    : device_(newDevice()), lanes_(packetWidth(device_.get(), settings.lanes)) {}

void EmbreeKernel::prepare(const Scene& scene, const RenderOptions& options, int slots) {
  frame_.inputs = kernel::ShadingInputs<float>::from(scene);
  buildScene(scene.spheres);
  frame_.scene = scene_.get();
  const auto slotCount = static_cast<std::size_t>(std::max(slots, 1));
  slots_.assign(slotCount, embree::Slot{});
  segmentsPerSlot_ = options.algorithm == Algorithm::two_pass
                         ? static_cast<std::size_t>(scene.render.maxDepth) * static_cast<std::size_t>(lanes_)
                         : 0;
  segments_.assign(slotCount * segmentsPerSlot_, PathSegment<float>{});
  // Embree walks its own BVH whatever the accel variant (the schema's own_accel).
  visitScalarVariant(options, [&]<Algorithm kAlgorithm, bool kBounceExit, Accel>() {
    span_ = spanFor<kAlgorithm, kBounceExit>(lanes_);
  });
}

// One sphere-point geometry, a float4 (x, y, z, radius) per sphere in
// scene order, so Embree's primID is the sphere's index. The scene is
// static and traced for many frames: the high-quality BVH build pays off.
void EmbreeKernel::buildScene(std::span<const Sphere> spheres) {
  scene_.reset(rtcNewScene(device_.get()));
  throwOnDeviceError(device_.get(), "creating the scene");
  rtcSetSceneBuildQuality(scene_.get(), RTC_BUILD_QUALITY_HIGH);
  const embree::GeometryHandle geometry(rtcNewGeometry(device_.get(), RTC_GEOMETRY_TYPE_SPHERE_POINT));
  auto* points = static_cast<float*>(rtcSetNewGeometryBuffer(geometry.get(), RTC_BUFFER_TYPE_VERTEX, 0,
                                                             RTC_FORMAT_FLOAT4, 4 * sizeof(float), spheres.size()));
  throwOnDeviceError(device_.get(), "allocating the sphere buffer");
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    points[4 * i + 0] = spheres[i].position.x;
    points[4 * i + 1] = spheres[i].position.y;
    points[4 * i + 2] = spheres[i].position.z;
    points[4 * i + 3] = spheres[i].radius;
  }
  rtcCommitGeometry(geometry.get());
  rtcAttachGeometry(scene_.get(), geometry.get());  // the scene takes its own reference
  rtcCommitScene(scene_.get());
  throwOnDeviceError(device_.get(), "building the scene");
}

}  // namespace rt
