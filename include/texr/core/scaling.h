// Exact rescaling by a power of two, for quantities whose scale does not matter (directions,
// the inverse transpose of a transform): multiplying by 2^k changes no bit of the mantissa,
// so normalising afterwards gives the same bits as before for ordinary values, while squared
// lengths and determinants of values near 1e300 or 1e-300 no longer overflow or underflow.
#pragma once
#include <cmath>

namespace texr {

// The k for which largest * 2^k lies in [1, 2); 0 for a largest of 0, infinity or NaN.
inline int unit_scale_exponent(double largest) {
    if (!(largest > 0.0) || !std::isfinite(largest)) return 0;
    int exponent = 0;
    std::frexp(largest, &exponent);  // largest = m 2^exponent, m in [1/2, 1)
    return 1 - exponent;
}

}  // namespace texr
