// PSNR and SSIM (see include/texr/bench/metrics.h).
#include "texr/bench/metrics.h"

#include <cmath>
#include <limits>

namespace texr {

double psnr(const FrameBytes& a, const FrameBytes& b, const std::vector<bool>& mask) {
    double sum = 0.0;
    std::size_t count = 0;
    for (std::size_t p = 0; p < mask.size(); ++p) {
        if (!mask[p]) continue;
        for (int c = 0; c < 3; ++c) {
            const double d = double(a.rgb[3 * p + std::size_t(c)]) - double(b.rgb[3 * p + std::size_t(c)]);
            sum += d * d;
        }
        count += 3;
    }
    if (count == 0) return std::numeric_limits<double>::quiet_NaN();  // nothing to compare
    if (sum == 0.0) return std::numeric_limits<double>::infinity();
    return 10.0 * std::log10(255.0 * 255.0 / (sum / double(count)));
}

namespace {

std::vector<double> luma(const FrameBytes& f) {
    std::vector<double> y(std::size_t(f.width) * std::size_t(f.height));
    for (std::size_t p = 0; p < y.size(); ++p)
        y[p] = 0.299 * f.rgb[3 * p] + 0.587 * f.rgb[3 * p + 1] + 0.114 * f.rgb[3 * p + 2];
    return y;
}

}  // namespace

double ssim(const FrameBytes& a, const FrameBytes& b, const std::vector<bool>& mask) {
    const int w = a.width, h = a.height, radius = 5;
    const double sigma = 1.5, c1 = std::pow(0.01 * 255, 2), c2 = std::pow(0.03 * 255, 2);
    double kernel[2 * radius + 1];
    double kernel_sum = 0.0;
    for (int k = -radius; k <= radius; ++k) kernel_sum += kernel[k + radius] = std::exp(-k * k / (2 * sigma * sigma));
    for (double& k : kernel) k /= kernel_sum;
    const std::vector<double> x = luma(a), y = luma(b);
    double total = 0.0;
    std::size_t count = 0;
    for (int py = 0; py < h; ++py)
        for (int px = 0; px < w; ++px) {
            if (!mask[std::size_t(py) * std::size_t(w) + std::size_t(px)]) continue;
            // Gaussian-weighted local statistics; the window is clipped at the frame edge.
            double weight = 0, mx = 0, my = 0, sxx = 0, syy = 0, sxy = 0;
            for (int dy = -radius; dy <= radius; ++dy) {
                const int qy = py + dy;
                if (qy < 0 || qy >= h) continue;
                for (int dx = -radius; dx <= radius; ++dx) {
                    const int qx = px + dx;
                    if (qx < 0 || qx >= w) continue;
                    const double k = kernel[dy + radius] * kernel[dx + radius];
                    const std::size_t q = std::size_t(qy) * std::size_t(w) + std::size_t(qx);
                    weight += k, mx += k * x[q], my += k * y[q];
                    sxx += k * x[q] * x[q], syy += k * y[q] * y[q], sxy += k * x[q] * y[q];
                }
            }
            mx /= weight, my /= weight;
            const double vx = sxx / weight - mx * mx, vy = syy / weight - my * my, cxy = sxy / weight - mx * my;
            total += ((2 * mx * my + c1) * (2 * cxy + c2)) / ((mx * mx + my * my + c1) * (vx + vy + c2));
            ++count;
        }
    return count ? total / double(count) : std::numeric_limits<double>::quiet_NaN();  // (nothing to compare)
}

}  // namespace texr
