#pragma once
// The Embree version layer: the one place that knows whether this build
// uses Embree 4 (<embree4/rtcore.h>, Debian 13, nixpkgs) or Embree 3
// (<embree3/rtcore.h>, Debian 12). CMake passes the major version found as
// RT_EMBREE_MAJOR (cmake/Dependencies.cmake). The kernel uses the types and
// calls both versions share (device, scene, sphere-point geometry, the
// RTCRayHit4/8/16 packets) directly and goes through this header only for
// what differs: how a packet is traced with a coherence hint, and the
// instance fields of a packet's hit. Embree's "Upgrading from Embree 3 to
// Embree 4" documentation section lists the API changes.
#if !defined(RT_EMBREE_MAJOR)
#error "RT_EMBREE_MAJOR is not defined: cmake/Dependencies.cmake passes Embree's major version (3 or 4)"
#elif RT_EMBREE_MAJOR == 4
#include <embree4/rtcore.h>
#elif RT_EMBREE_MAJOR == 3
#include <embree3/rtcore.h>
#else
#error "RT_EMBREE_MAJOR must be 3 or 4"
#endif

#if RTC_VERSION_MAJOR != RT_EMBREE_MAJOR
#error "the Embree header found is not the major version CMake found"
#endif

namespace rt::embree::api {

// How coherent a packet's rays are, Embree's traversal hint: the primary
// rays of adjacent pixels are, the bounced rays are not.
enum class Coherence { coherent, incoherent };

// Embree 4 passes the hint in RTCIntersectArguments (flags, after
// rtcInitIntersectArguments; there is no RTCIntersectContext any more) and
// takes it after the packet; Embree 3 passes it in an RTCIntersectContext
// (flags, after rtcInitIntersectContext) before the packet.
#if RT_EMBREE_MAJOR == 4
using QueryArguments = RTCIntersectArguments;
inline QueryArguments queryArguments(Coherence coherence) {
  RTCIntersectArguments args;
  rtcInitIntersectArguments(&args);
  args.flags = coherence == Coherence::coherent ? RTC_RAY_QUERY_FLAG_COHERENT : RTC_RAY_QUERY_FLAG_INCOHERENT;
  return args;
}
template <typename Trace, typename Packet>
void traceWith(Trace trace, const int* valid, RTCScene scene, QueryArguments& args, Packet& packet) {
  trace(valid, scene, &packet, &args);
}
#else
using QueryArguments = RTCIntersectContext;
inline QueryArguments queryArguments(Coherence coherence) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags =
      coherence == Coherence::coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  return context;
}
template <typename Trace, typename Packet>
void traceWith(Trace trace, const int* valid, RTCScene scene, QueryArguments& context, Packet& packet) {
  trace(valid, scene, &context, &packet);
}
#endif

// The trace call of each packet width, in this version's argument order.
inline void intersect(const int* valid, RTCScene scene, QueryArguments& args, RTCRayHit4& packet) {
  traceWith(rtcIntersect4, valid, scene, args, packet);
}
inline void intersect(const int* valid, RTCScene scene, QueryArguments& args, RTCRayHit8& packet) {
  traceWith(rtcIntersect8, valid, scene, args, packet);
}
inline void intersect(const int* valid, RTCScene scene, QueryArguments& args, RTCRayHit16& packet) {
  traceWith(rtcIntersect16, valid, scene, args, packet);
}

// Lane i of a packet's hit before tracing: no geometry, no instance.
// Embree 4.3 builds with instance arrays (RTC_GEOMETRY_INSTANCE_ARRAY) add
// an instance primitive id beside the instance id.
template <typename Hit>
void clearHit(Hit& hit, int i) {
  hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
  hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
#if defined(RTC_GEOMETRY_INSTANCE_ARRAY)
  hit.instPrimID[0][i] = RTC_INVALID_GEOMETRY_ID;
#endif
}

// Whether this Embree culls a sphere's back face: then a ray that starts
// inside a sphere misses it, where the model (docs/render-model.md
// section 3) takes the far hit. Embree 4.1 added the build option
// EMBREE_BACKFACE_CULLING_SPHERES (default off) and the device property
// that reports it; Embree 3 and 4.0 have neither and never cull spheres.
inline bool cullsSphereBackFaces([[maybe_unused]] RTCDevice device) {
#if RT_EMBREE_MAJOR == 4 && RTC_VERSION >= 40100
  return rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_BACKFACE_CULLING_SPHERES_ENABLED) != 0;
#else
  return false;
#endif
}

}  // namespace rt::embree::api
