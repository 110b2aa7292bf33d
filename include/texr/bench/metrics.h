// Image error metrics for the benchmarks, on 8-bit sRGB RGB frames (what a viewer sees).
// Both are computed only where `mask` is true (the pixels a scene's surfaces cover), so an
// empty sky does not flatter a filter.
//   PSNR = 10 log10(255^2 / MSE), MSE over the masked pixels' three channels.
//   SSIM (Wang et al. 2004) on luma Y = (0.299 R + 0.587 G + 0.114 B), Gaussian window
//   (sigma 1.5, 11x11), C1 = (0.01 * 255)^2, C2 = (0.03 * 255)^2, averaged over masked
//   pixels' windows.
#pragma once
#include <cstdint>
#include <vector>

namespace texr {

struct FrameBytes {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb;  // 3 bytes per pixel, row 0 at the top
};

// PSNR is +infinity when the masked pixels are identical. Both are NaN for an empty mask (a
// scene whose surfaces cover no pixel): nothing was compared, which is no score, not a
// perfect one.
double psnr(const FrameBytes& a, const FrameBytes& b, const std::vector<bool>& mask);
double ssim(const FrameBytes& a, const FrameBytes& b, const std::vector<bool>& mask);

}  // namespace texr
