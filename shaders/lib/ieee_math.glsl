// Division and square root rounded to nearest, as IEEE 754 and the C++ twins round them.
// Vulkan only requires a shader's float division to be within 2.5 ULP and its square root as
// close as 1 / inversesqrt(x), and NVIDIA's division (driver 580, H200) is that loose: with
// plain `/` the trace kernels' t differed from the CPU reference's in the last bits
// (docs/ARCHITECTURE.md, "Bit for bit on other devices"). Here both are computed in double and
// rounded once to float.
// That is the correctly rounded float result even when the double operation is a double ULP or
// two off: a quotient or root of floats is at least 2^-50 (relative) away from a midpoint
// between two floats, and a double ULP is at most 2^-52 of the value. Subnormal inputs or results stay exact only
// where the device keeps float denormals (lavapipe does).
#ifndef HRPP_IEEE_MATH_GLSL
#define HRPP_IEEE_MATH_GLSL

float ieee_div(float a, float b) { return float(double(a) / double(b)); }

float ieee_sqrt(float x) { return float(sqrt(double(x))); }

#endif  // HRPP_IEEE_MATH_GLSL
