// The height-field surface of image-based stand-ins (enhanced billboards, view atlas views): its
// constants, included by C++ (which static_asserts against them) and by GLSL
// (height_field.glsl). Plain #defines only: both languages must parse this file.
// A covered texel is a top at its stored depth (tilted up to HF_TOP_MAX_SLOPE in both walks: by
// its stored normal in the view atlas's, by its linked neighbours' depths in the billboards'); two neighbouring covered texels continue one surface, joined by a wall, when
// their depth step is within
//   (HF_SLOPE_TOLERANCE * slope + HF_CURVATURE_TEXELS) * texel + HF_QUANTA * quantum,
// slope being the steeper of their stored normals' depth change per texel (capped at
// HF_MAX_SLOPE) and quantum one step of the stored depth; a larger step is a depth edge, where the
// capture saw one surface in front of another and knows nothing of the space between them.
#ifndef STANDIN_HEIGHT_FIELD_H
#define STANDIN_HEIGHT_FIELD_H

#define HF_SLOPE_TOLERANCE 1.5  // normals are sampled at texel centres: allow half as much again
#define HF_CURVATURE_TEXELS 0.5 // a curved surface turns between two normals: half a texel
#define HF_QUANTA 2.0           // a step of two depth codes is rounding, not an edge
#define HF_MAX_SLOPE 8.0        // texels of depth per texel (about 83 degrees): steeper is a wall
#define HF_DEPTH_CODES 65535.0  // the one depth encoding: d in [0, 1] as a 16-bit code (surface_image.h)
// A covered texel's top tilts by its stored normal up to this slope (texels of depth per texel,
// about 72 degrees; the view atlas's and the billboards' walks): steeper normals are unsure near an
// outline, and a steeper top would reach far past its texel's depth
#define HF_TOP_MAX_SLOPE 3.0

// what a ray met in one texel column (hf_cross_column)
#define HF_MISS 0  // nothing in this column
#define HF_TOP 1   // the column's top
#define HF_WALL 2  // the wall it entered through, to a neighbour of the same surface
#define HF_UNDER 3 // entered below the top, not through a wall of this surface: space the capture did not see

#endif
