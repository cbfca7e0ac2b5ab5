#pragma once
// The demo's scene without ParaView (Scripts/demo_simulation.py builds the same through the
// filters): guides as Hair Strands grows them on the bundled body's automatic scalp (seed 1,
// 30 cm, wavy, combed towards (0, −1, −0.3) with weight 0.35), the head and trunk tables,
// the head shaking ±0.5 rad at 1 Hz about the neck, and a 0.5 m/s wind from the front.
#include "ProjectiveScenes.h"
#include "render/HairInterpolation.h"
#include "scene/Scene.h"
#include "simulation/Simulation.h"
#include "strands/GuideStrand.h"

#include <string>
#include <vector>

namespace hair
{

/// The demo guides' length [m] and hair type.
constexpr double DemoGuideLength = 0.30;
constexpr HairType DemoHairType = HairType::Wavy;

/// `count` guides of `elements` elements (10 for the Super-Helix run, 40 for the
/// projective one).
Status demoGuides(const BundledBody& body, int count, int elements,
                  std::vector<GuideStrand>& guides);
/// `count` guides of each of `presets`, grown as above (the wavy preset replaced): count ×
/// presets.size() roots spread over the scalp, the presets taking turns along the roots'
/// Hilbert curve (guide k has presets[k mod presets.size()]), so that every patch of the
/// scalp has some of each.
Status demoGuides(const BundledBody& body, int count, int elements,
                  const std::vector<HairType>& presets, std::vector<GuideStrand>& guides);
/// The parts, the head's motion (carrying the roots and the head's table), the wind.
Scene demoScene(const BundledBody& body);

/// Frame `frame` of a run's guides as Hair Simulation's output 0 hands them to Hair
/// Interpolation: drawn from the state at `pointsPerElement` points per element
/// (simulation/GuideDrawing), with the material frames, and the per-point scalars named in
/// `scalars`.
Status drawnCurves(const Simulation& sim, int frame, int pointsPerElement,
                   const std::vector<std::string>& scalars, GuideCurves& curves);

} // namespace hair
