// Fig 3.6 of the thesis: the explicit projector parameters (baseline l_i, projection angle
// theta_i, tilt angle phi_i; eqs 3.6-3.8) against the stripe number, drawn with OpenCV.
#pragma once

#include <body_scan_driver/pair_model.h>

#include <opencv2/core/mat.hpp>

namespace body_scan_calib {

// Three stacked panels (BGR image). Estimated planes are dots; reference planes (e.g. the
// simulator's true ones), if given, a thin line. NaN planes are left out.
cv::Mat plotProjectorParameters(const body_scan_driver::StripePlaneProjector& estimated,
                                const body_scan_driver::StripePlaneProjector* reference = nullptr);

}  // namespace body_scan_calib
