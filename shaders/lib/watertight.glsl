// Watertight ray–triangle test (Woop, Benthin, Wald 2013, JCGT 2(1)): the GLSL twin of
// host/trace/watertight.h. Edge functions in sheared space; recomputed in double when one is
// exactly zero, so a ray through a shared edge or vertex hits exactly one triangle. Both faces.
#ifndef HRPP_WATERTIGHT_GLSL
#define HRPP_WATERTIGHT_GLSL

#include "ray_setup.glsl"

// On a hit within [r.tmin, tmax]: true, with t and the barycentrics u (of v1) and v (of v2).
bool intersect_triangle(RaySetup r, vec3 v0, vec3 v1, vec3 v2, float tmax, out float t_hit,
                        out float u_hit, out float v_hit) {
  precise vec3 a = v0 - r.origin;
  precise vec3 b = v1 - r.origin;
  precise vec3 c = v2 - r.origin;
  precise float ax = a[r.kx] - r.sx * a[r.kz];
  precise float ay = a[r.ky] - r.sy * a[r.kz];
  precise float bx = b[r.kx] - r.sx * b[r.kz];
  precise float by = b[r.ky] - r.sy * b[r.kz];
  precise float cx = c[r.kx] - r.sx * c[r.kz];
  precise float cy = c[r.ky] - r.sy * c[r.kz];
  precise float u = cx * by - cy * bx;
  precise float v = ax * cy - ay * cx;
  precise float w = bx * ay - by * ax;
  if (u == 0.0 || v == 0.0 || w == 0.0) {
    precise double du = double(cx) * double(by) - double(cy) * double(bx);
    precise double dv = double(ax) * double(cy) - double(ay) * double(cx);
    precise double dw = double(bx) * double(ay) - double(by) * double(ax);
    u = float(du);
    v = float(dv);
    w = float(dw);
  }
  t_hit = 0.0;
  u_hit = 0.0;
  v_hit = 0.0;
  if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) return false;
  precise float det = u + v + w;
  if (det == 0.0) return false;
  precise float az = r.sz * a[r.kz];
  precise float bz = r.sz * b[r.kz];
  precise float cz = r.sz * c[r.kz];
  // t from the normalised barycentrics, which stay in [0, 1] on a hit: the sum of edge
  // functions × z overflows for triangles ~1e17 across at distance 1e4.
  precise float inv_det = ieee_div(1.0, det);
  precise float b0 = u * inv_det;
  precise float b1 = v * inv_det;
  precise float b2 = w * inv_det;
  precise float t = b0 * az + b1 * bz + b2 * cz;
  if (!(t >= r.tmin && t <= tmax)) return false;
  t_hit = t;
  u_hit = b1;
  v_hit = b2;
  return true;
}

#endif  // HRPP_WATERTIGHT_GLSL
