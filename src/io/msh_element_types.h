// MSH element types (Gmsh reference manual, "MSH file format") of the 3D elements stickslip reads.
#pragma once

namespace stickslip::msh {

inline constexpr int kTet4 = 4;
inline constexpr int kHex8 = 5;
inline constexpr int kTet10 = 11;
inline constexpr int kHex20 = 17;
inline constexpr int kPrism6 = 6;
inline constexpr int kPrism15 = 18;
inline constexpr int kPyramid5 = 7;
inline constexpr int kPyramid13 = 19;

}  // namespace stickslip::msh
