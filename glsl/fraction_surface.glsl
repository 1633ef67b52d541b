// Whether a fraction texel lies on a fragment's or another texel's surface (docs/DESIGN.md §5.14): the
// shading's upsampling and the fraction's filter ask it alike.

// How far a texel's 1/w may lie from the plane and still be its surface: a sliver of the depth (a curved
// surface leaves its tangent plane within a pixel or two; the upsampling adds the plane's change over a pixel).
const float kPlaneToleranceOfDepth = 0.005;
// The normals' agreement: (n.n')^16, a half at 16 degrees apart, under 1% beyond 37.
const float kNormalPower = 16.0;
