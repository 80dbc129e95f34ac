// Embree 3 and Embree 4 behind one set of calls, for every target that links hrpp_embree (the
// CMake target that finds either and sets HRPP_EMBREE_MAJOR): the header of that version, and
// the single-ray queries with Embree's default query settings. Embree 3 passes an initialised
// RTCIntersectContext; Embree 4 drops it for optional argument structs. Everything else hrpp
// calls (devices, geometry buffers, scene flags, build quality) is the same in both.
#pragma once

#if HRPP_EMBREE_MAJOR >= 4
#include <embree4/rtcore.h>
#else
#include <embree3/rtcore.h>
#endif

namespace hrpp::embree {

// rtcIntersect1: the closest hit within [tnear, tfar]; rh.hit.geomID stays invalid on a miss.
inline void intersect1(RTCScene scene, RTCRayHit& rh) {
#if HRPP_EMBREE_MAJOR >= 4
  rtcIntersect1(scene, &rh);
#else
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcIntersect1(scene, &context, &rh);
#endif
}

// rtcOccluded1: sets ray.tfar to -inf when anything lies within [tnear, tfar].
inline void occluded1(RTCScene scene, RTCRay& ray) {
#if HRPP_EMBREE_MAJOR >= 4
  rtcOccluded1(scene, &ray);
#else
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcOccluded1(scene, &context, &ray);
#endif
}

}  // namespace hrpp::embree
