// Division and square root rounded to nearest, as IEEE 754 and the C++ twins round them.
// Vulkan only requires a shader's float division to be within 2.5 ULP and its square root as
// close as 1 / inversesqrt(x), and NVIDIA's division (driver 580, H200) is that loose: with
// plain `/` the trace kernels' t differed from the CPU reference's in the last bits
// (docs/DEVICES.md, "Bit for bit on other devices"). Here both are computed in double and
// rounded once to float.
// That is the correctly rounded float result even when the double operation is a double ULP or
// two off: a quotient or root of floats is at least 2^-50 (relative) away from a midpoint
// between two floats, and a double ULP is at most 2^-52 of the value. Subnormal inputs or results stay exact only
// where the device keeps float denormals (lavapipe does; elsewhere ComputePipeline asks for
// DenormPreserve when the device offers it, host/vk/float_controls.h).
// The shared shading headers (shaders/shared/) call these by the same names as C++, where
// glsl_cpp.h defines them as plain division, std::sqrt and glm's normalize, length and refract;
// the vector forms below compute what glm computes, in glm's order and with each step rounded:
// dot(v, v) = (x·x + y·y) + z·z, inversesqrt(x) = 1 / sqrt(x), normalize(v) = v · inversesqrt(dot).
#ifndef HRPP_IEEE_MATH_GLSL
#define HRPP_IEEE_MATH_GLSL

// double(x), built from x's bits. Exact, as double(x) is, but opaque to the compiler: Mesa 25's
// NIR turns double(float(y)) back into y for a double y (a rounding dropped, not an exact
// rewrite), so a quotient by ieee_sqrt's result would divide by the unrounded root.
double exact_double(float x) {
  const uint bits = floatBitsToUint(x);
  const uint sign = bits & 0x80000000u, exponent = (bits >> 23) & 0xFFu;
  const uint mantissa = bits & 0x7FFFFFu;
  if (exponent == 0u) {  // zero or subnormal: mantissa · 2^-149
    const double magnitude = double(mantissa) * 1.4012984643248171e-45LF;
    return sign != 0u ? -magnitude : magnitude;
  }
  const uint wide_exponent = exponent == 0xFFu ? 0x7FFu : exponent + 896u;  // bias 127 → 1023
  return packDouble2x32(uvec2(mantissa << 29, sign | (wide_exponent << 20) | (mantissa >> 3)));
}

float ieee_div(float a, float b) { return float(exact_double(a) / exact_double(b)); }

float ieee_sqrt(float x) { return float(sqrt(exact_double(x))); }

vec3 ieee_div(vec3 a, float b) { return vec3(ieee_div(a.x, b), ieee_div(a.y, b), ieee_div(a.z, b)); }

float ieee_inversesqrt(float x) { return ieee_div(1.0, ieee_sqrt(x)); }

float ieee_dot(vec3 a, vec3 b) {
  precise float d = a.x * b.x + a.y * b.y + a.z * b.z;
  return d;
}

// glm's cross, each product rounded: a driver's own cross may fuse a product into the
// subtraction, which turns an exact 0 (a wall's normal with z = 0) into the product's rounding
// error, and the sign of that flips the orthonormal basis that samples directions (bsdf.h).
vec3 ieee_cross(vec3 a, vec3 b) {
  precise vec3 c = vec3(a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y);
  return c;
}

float ieee_length(vec3 v) { return ieee_sqrt(ieee_dot(v, v)); }

vec3 ieee_normalize(vec3 v) {
  precise vec3 n = v * ieee_inversesqrt(ieee_dot(v, v));
  return n;
}

// GLSL's refract (glm's too): eta·i - (eta·dot(n, i) + sqrt(k))·n, or 0 where k < 0.
vec3 ieee_refract(vec3 i, vec3 n, float eta) {
  precise float d = ieee_dot(n, i);
  precise float k = 1.0 - eta * eta * (1.0 - d * d);
  if (k < 0.0) return vec3(0.0);
  precise vec3 r = eta * i - (eta * d + ieee_sqrt(k)) * n;
  return r;
}

#endif  // HRPP_IEEE_MATH_GLSL
