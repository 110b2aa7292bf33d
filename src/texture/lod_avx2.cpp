// The batched span walk's second pass in AVX2 lanes (see include/texr/texture/lod_avx2.h).
#include "texr/texture/lod_avx2.h"

#include <cstdlib>
#include <cstring>

#include "texr/texture/minify.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define TEXR_AVX2_LANES 1
#endif

namespace texr {

#if TEXR_AVX2_LANES

bool avx2_lanes_available() {
    static const bool available = [] {
        const char* off = std::getenv("TEXR_NO_AVX2");
        return __builtin_cpu_supports("avx2") && !(off && *off && std::strcmp(off, "0") != 0);
    }();
    return available;
}

namespace {
// (Functions rather than lambdas: a lambda does not take its caller's target attribute.)
__attribute__((target("avx2"), always_inline)) inline __m256d derivative(double d_prime, __m256d value, double dq,
                                                                          __m256d inv_q) {  // uv_derivatives_from_inverse_q
    return _mm256_mul_pd(_mm256_sub_pd(_mm256_set1_pd(d_prime), _mm256_mul_pd(value, _mm256_set1_pd(dq))), inv_q);
}
__attribute__((target("avx2"), always_inline)) inline __m256d squared(__m256d du, __m256d dv, __m256d w, __m256d h) {
    const __m256d a = _mm256_mul_pd(w, du), b = _mm256_mul_pd(h, dv);  // squared_texels
    return _mm256_add_pd(_mm256_mul_pd(a, a), _mm256_mul_pd(b, b));
}
}  // namespace

__attribute__((target("avx2"))) int levels_of_detail_avx2(const TextureHomography& h, int width, int height, bool stepped,
                                                         int n, double* q, double* u, double* v, double* lambda) {
    using minify_detail::log2_table;
    const __m256d w = _mm256_set1_pd(double(width)), ht = _mm256_set1_pd(double(height)), one = _mm256_set1_pd(1.0);
    int k = 0;
    for (; k + 3 < n; k += 4) {
        const __m256d inv_q = _mm256_div_pd(one, _mm256_loadu_pd(q + k));
        _mm256_storeu_pd(q + k, inv_q);
        __m256d uk = _mm256_loadu_pd(u + k), vk = _mm256_loadu_pd(v + k);
        if (stepped) {
            uk = _mm256_mul_pd(uk, inv_q), vk = _mm256_mul_pd(vk, inv_q);
            _mm256_storeu_pd(u + k, uk), _mm256_storeu_pd(v + k, vk);
        }
        const __m256d rho_x =
            squared(derivative(h.u_prime.dx, uk, h.q.dx, inv_q), derivative(h.v_prime.dx, vk, h.q.dx, inv_q), w, ht);
        const __m256d rho_y =
            squared(derivative(h.u_prime.dy, uk, h.q.dy, inv_q), derivative(h.v_prime.dy, vk, h.q.dy, inv_q), w, ht);
        // (as level_of_detail_lanes: max(y, max(x, 0)) picks as std::max does, NaN included)
        const __m256d rho2 = _mm256_max_pd(rho_y, _mm256_max_pd(rho_x, _mm256_setzero_pd()));
        const __m256i bits = _mm256_castpd_si256(rho2);
        const __m256i biased = _mm256_and_si256(_mm256_srli_epi64(bits, 52), _mm256_set1_epi64x(0x7ff));
        const __m256i special = _mm256_or_si256(_mm256_cmpeq_epi64(biased, _mm256_setzero_si256()),
                                                _mm256_cmpeq_epi64(biased, _mm256_set1_epi64x(0x7ff)));
        if (_mm256_movemask_pd(_mm256_castsi256_pd(special)) != 0) {
            alignas(32) double r[4];
            _mm256_store_pd(r, rho2);
            for (int j = 0; j < 4; ++j) lambda[k + j] = minify_detail::level_of_detail_of_squared(r[j]);
            continue;
        }
        const __m256i fraction = _mm256_and_si256(bits, _mm256_set1_epi64x(0x000fffffffffffffLL));
        const __m256d m = _mm256_castsi256_pd(_mm256_or_si256(fraction, _mm256_set1_epi64x(0x3ff0000000000000LL)));
        alignas(32) long long index[4];
        _mm256_store_si256(reinterpret_cast<__m256i*>(index), _mm256_srli_epi64(fraction, 45));
        const __m256d x = _mm256_sub_pd(
            _mm256_mul_pd(m, _mm256_set_pd(log2_table.inverse[index[3]], log2_table.inverse[index[2]],
                                           log2_table.inverse[index[1]], log2_table.inverse[index[0]])),
            one);
        __m256d ln = _mm256_add_pd(_mm256_set1_pd(-1.0 / 4.0), _mm256_mul_pd(x, _mm256_set1_pd(1.0 / 5.0)));
        ln = _mm256_add_pd(_mm256_set1_pd(1.0 / 3.0), _mm256_mul_pd(x, ln));
        ln = _mm256_add_pd(_mm256_set1_pd(-1.0 / 2.0), _mm256_mul_pd(x, ln));
        ln = _mm256_add_pd(one, _mm256_mul_pd(x, ln));
        ln = _mm256_mul_pd(x, ln);
        // The exponents, the low 32 bits of each 64-bit lane, as four ints, less 1023.
        const __m128i e = _mm_sub_epi32(
            _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(biased, _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6))),
            _mm_set1_epi32(1023));
        const __m256d log2 = _mm256_add_pd(
            _mm256_add_pd(_mm256_cvtepi32_pd(e), _mm256_set_pd(log2_table.log2_c[index[3]], log2_table.log2_c[index[2]],
                                                               log2_table.log2_c[index[1]], log2_table.log2_c[index[0]])),
            _mm256_mul_pd(ln, _mm256_set1_pd(1.4426950408889634)));
        _mm256_storeu_pd(lambda + k, _mm256_mul_pd(_mm256_set1_pd(0.5), log2));
    }
    return k;
}

#else

bool avx2_lanes_available() { return false; }
int levels_of_detail_avx2(const TextureHomography&, int, int, bool, int, double*, double*, double*, double*) { return 0; }

#endif

}  // namespace texr
