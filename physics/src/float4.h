// Float4: four floats handled by one instruction (a lane each), for the
// contact solver's wide rows (contact_solver.h). Written with the GCC/Clang
// vector extension, so +, -, * and / work lane by lane on any target the
// compilers support (SSE2 on x86-64, NEON on ARM); the few operations the
// extension lacks are the plain functions below.
#pragma once

#include <bit>
#include <cmath>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace tumble::physics {

using Float4 = float __attribute__((vector_size(16)));
// What a comparison of two Float4 gives: all bits set in a lane where it
// holds, none where it does not.
using Mask4 = int __attribute__((vector_size(16)));

inline Float4 splat4(float x) { return Float4{x, x, x, x}; }

// a where mask holds, b elsewhere.
inline Float4 select4(Mask4 mask, Float4 a, Float4 b) {
  return std::bit_cast<Float4>((mask & std::bit_cast<Mask4>(a)) | (~mask & std::bit_cast<Mask4>(b)));
}

inline Float4 max4(Float4 a, Float4 b) { return select4(a > b, a, b); }
inline Float4 min4(Float4 a, Float4 b) { return select4(a < b, a, b); }

// Whether any lane of mask is set.
inline bool any4(Mask4 mask) {
#if defined(__SSE__)
  return _mm_movemask_ps(std::bit_cast<__m128>(mask)) != 0;
#else
  return (mask[0] | mask[1] | mask[2] | mask[3]) != 0;
#endif
}

// Whether every lane of mask is set.
inline bool all4(Mask4 mask) {
#if defined(__SSE__)
  return _mm_movemask_ps(std::bit_cast<__m128>(mask)) == 0xf;
#else
  return (mask[0] & mask[1] & mask[2] & mask[3]) != 0;
#endif
}

inline Float4 sqrt4(Float4 x) {
#if defined(__SSE__)
  return std::bit_cast<Float4>(_mm_sqrt_ps(std::bit_cast<__m128>(x)));
#else
  return Float4{std::sqrt(x[0]), std::sqrt(x[1]), std::sqrt(x[2]), std::sqrt(x[3])};
#endif
}

// A vector of three components, each four lanes wide: lane l holds the l-th
// of four 3-vectors.
struct Vec3x4 {
  Float4 x, y, z;
};

inline Vec3x4 operator+(const Vec3x4& a, const Vec3x4& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3x4 operator-(const Vec3x4& a, const Vec3x4& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3x4 operator*(Float4 s, const Vec3x4& a) { return {s * a.x, s * a.y, s * a.z}; }
inline Float4 dot4(const Vec3x4& a, const Vec3x4& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

}  // namespace tumble::physics
