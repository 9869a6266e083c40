// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/sim/ProceduralTexture.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <opencv2/imgproc.hpp>
#include <random>
#include <stdexcept>
#include <tuple>
#include <vector>

namespace emslam::sim
{
namespace
{
/** Textures kept by generate(): about 100 MB at most (512² floats and mipmaps). */
constexpr std::size_t MAX_KEPT_TEXTURES = 64;

const char* const KINDS[] = {"noise",  "bricks", "tiles",  "repetitive",
                             "poster", "wood",   "gravel", "bush"};

/** Multi-scale value noise with periods from `max_period` down to 2 texels,
 * wrapping at `size`; amplitude of an octave grows with sqrt(period). Result
 * has zero mean and roughly unit standard deviation. */
cv::Mat valueNoise(std::mt19937_64& rng, int size, int max_period)
{
    cv::Mat acc(size, size, CV_32F, cv::Scalar(0));
    std::uniform_real_distribution<float> u(-1.0F, 1.0F);
    double norm = 0.0;
    for (int period = std::min(max_period, size); period >= 2; period /= 2)
    {
        const int n = size / period;
        std::vector<float> lattice(static_cast<std::size_t>(n * n));
        for (auto& v : lattice)
        {
            v = u(rng);
        }
        const auto amp = static_cast<float>(std::pow(static_cast<double>(period), 0.3));
        norm += amp * amp / 3.0;
        for (int y = 0; y < size; ++y)
        {
            const double fy = static_cast<double>(y) / period;
            const int y0 = static_cast<int>(fy) % n;
            const int y1 = (y0 + 1) % n;
            double ty = fy - std::floor(fy);
            ty = ty * ty * (3 - 2 * ty);
            auto* row = acc.ptr<float>(y);
            for (int x = 0; x < size; ++x)
            {
                const double fx = static_cast<double>(x) / period;
                const int x0 = static_cast<int>(fx) % n;
                const int x1 = (x0 + 1) % n;
                double tx = fx - std::floor(fx);
                tx = tx * tx * (3 - 2 * tx);
                const double a = lattice[static_cast<std::size_t>(y0 * n + x0)];
                const double b = lattice[static_cast<std::size_t>(y0 * n + x1)];
                const double c = lattice[static_cast<std::size_t>(y1 * n + x0)];
                const double d = lattice[static_cast<std::size_t>(y1 * n + x1)];
                const double v = (a * (1 - tx) + b * tx) * (1 - ty) + (c * (1 - tx) + d * tx) * ty;
                row[x] += static_cast<float>(amp * v);
            }
        }
    }
    acc *= static_cast<float>(1.0 / std::sqrt(norm));
    return acc;
}

/** Periodic rectangular cells ("bricks" with an offset every other row,
 * "tiles" aligned): mortar lines dark, per-cell intensity random unless
 * `uniform`. */
void cells(
    cv::Mat& img,
    std::mt19937_64& rng,
    int cell_w,
    int cell_h,
    bool offset_rows,
    bool uniform,
    float mortar)
{
    const int size = img.cols;
    const int nx = size / cell_w;
    const int ny = size / cell_h;
    std::uniform_real_distribution<float> u(-35.0F, 35.0F);
    std::vector<float> shade(static_cast<std::size_t>(nx * ny));
    for (auto& s : shade)
    {
        s = uniform ? 0.0F : u(rng);
    }
    for (int y = 0; y < size; ++y)
    {
        const int cy = y / cell_h;
        const int off = (offset_rows && (cy % 2 == 1)) ? cell_w / 2 : 0;
        auto* row = img.ptr<float>(y);
        for (int x = 0; x < size; ++x)
        {
            const int xs = (x + off) % size;
            const int cx = xs / cell_w;
            const bool line = (y % cell_h) < 2 || (xs % cell_w) < 2;
            row[x] += line ? mortar : shade[static_cast<std::size_t>(cy * nx + cx)];
        }
    }
}
}  // namespace

bool ProceduralTexture::isKnownKind(const std::string& kind)
{
    return std::find(std::begin(KINDS), std::end(KINDS), kind) != std::end(KINDS);
}

std::string ProceduralTexture::knownKinds()
{
    std::string s;
    for (const char* k : KINDS)
    {
        s += (s.empty() ? "" : ", ") + std::string(k);
    }
    return s;
}

ProceduralTexture ProceduralTexture::generate(const std::string& kind, std::uint64_t seed, int size)
{
    using Key = std::tuple<std::string, std::uint64_t, int>;
    static std::mutex mutex;
    static std::map<Key, ProceduralTexture> kept;
    const Key key{kind, seed, size};
    {
        const std::lock_guard<std::mutex> lock(mutex);
        const auto it = kept.find(key);
        if (it != kept.end())
        {
            return it->second;
        }
    }
    ProceduralTexture t = generateNew(kind, seed, size);
    const std::lock_guard<std::mutex> lock(mutex);
    if (kept.size() >= MAX_KEPT_TEXTURES)
    {
        kept.clear();  // a bound, not an LRU: worlds use a few dozen textures
    }
    kept.emplace(key, t);
    return t;
}

ProceduralTexture ProceduralTexture::generateNew(
    const std::string& kind, std::uint64_t seed, int size)
{
    if (!isKnownKind(kind))
    {
        throw std::invalid_argument(
            "unknown texture kind '" + kind + "' (expected one of: " + knownKinds() + ")");
    }
    if (size < 16 || (size & (size - 1)) != 0)
    {
        throw std::invalid_argument("texture size must be a power of two >= 16");
    }
    std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ULL + 0x2545F4914F6CDD1DULL);
    ProceduralTexture t;
    cv::Mat noise = valueNoise(rng, size, kind == "gravel" ? 16 : size / 2);
    std::uniform_real_distribution<float> base_u(90.0F, 160.0F);
    const float base = base_u(rng);
    cv::Mat img(size, size, CV_32F, cv::Scalar(base));
    if (kind == "noise" || kind == "gravel")
    {
        img += noise * 40.0F;
    }
    else if (kind == "bricks")
    {
        cells(img, rng, size / 8, size / 16, true, false, -60.0F);
        img += noise * 22.0F;
    }
    else if (kind == "tiles")
    {
        cells(img, rng, size / 4, size / 4, false, false, -55.0F);
        img += noise * 22.0F;
    }
    else if (kind == "repetitive")
    {
        // Identical cells: the only non-periodic content is faint noise.
        cells(img, rng, size / 8, size / 8, false, true, -70.0F);
        for (int y = 0; y < size; ++y)
        {
            for (int x = 0; x < size; ++x)
            {
                const int cx = x % (size / 8);
                const int cy = y % (size / 8);
                if (std::abs(cx - size / 16) + std::abs(cy - size / 16) < size / 32)
                {
                    img.at<float>(y, x) += 60.0F;
                }
            }
        }
        img += noise * 4.0F;
    }
    else if (kind == "poster")
    {
        std::uniform_int_distribution<int> pos(0, size - 1);
        std::uniform_int_distribution<int> ext(size / 16, size / 3);
        std::uniform_real_distribution<float> val(-90.0F, 90.0F);
        for (int i = 0; i < 14; ++i)
        {
            const cv::Point c(pos(rng), pos(rng));
            const float v = base + val(rng);
            if (i % 2 == 0)
            {
                cv::rectangle(
                    img, cv::Rect(c.x, c.y, ext(rng), ext(rng)), cv::Scalar(v), cv::FILLED);
            }
            else
            {
                cv::circle(img, c, ext(rng) / 2, cv::Scalar(v), cv::FILLED);
            }
        }
        cv::rectangle(img, cv::Rect(0, 0, size, size), cv::Scalar(30), size / 32);
        img += noise * 15.0F;
    }
    else if (kind == "wood")
    {
        cv::Mat streaks = valueNoise(rng, size, size / 4);
        for (int y = 0; y < size; ++y)
        {
            for (int x = 0; x < size; ++x)
            {
                img.at<float>(y, x) += 35.0F * streaks.at<float>(y / 16, x) - 20.0F;
            }
        }
        cv::rectangle(img, cv::Rect(0, 0, size, size), cv::Scalar(40), size / 24);
        img += noise * 12.0F;
    }
    else  // bush
    {
        cv::Mat coarse = valueNoise(rng, size, size / 8);
        img = base - 40.0F + noise * 30.0F + coarse * 45.0F;
    }
    cv::max(img, 5.0, img);
    cv::min(img, 250.0, img);
    t.m_img = img;
    t.m_mask = size - 1;
    t.buildMipmaps();
    return t;
}

void ProceduralTexture::buildMipmaps()
{
    m_mips.clear();
    cv::Mat prev = m_img;
    while (prev.cols > 4)
    {
        cv::Mat next(prev.rows / 2, prev.cols / 2, CV_32F);
        for (int y = 0; y < next.rows; ++y)
        {
            const float* r0 = prev.ptr<float>(2 * y);
            const float* r1 = prev.ptr<float>(2 * y + 1);
            auto* o = next.ptr<float>(y);
            for (int x = 0; x < next.cols; ++x)
            {
                o[x] = 0.25F * (r0[2 * x] + r0[2 * x + 1] + r1[2 * x] + r1[2 * x + 1]);
            }
        }
        m_mips.push_back(next);
        prev = next;
    }
}

float ProceduralTexture::bilinearWrap(const cv::Mat& m, int mask, double s, double t)
{
    const double fs = s - 0.5;
    const double ft = t - 0.5;
    const double is = std::floor(fs);
    const double it = std::floor(ft);
    const auto as = static_cast<float>(fs - is);
    const auto at = static_cast<float>(ft - it);
    const int x0 = static_cast<int>(static_cast<long long>(is) & mask);
    const int y0 = static_cast<int>(static_cast<long long>(it) & mask);
    const int x1 = (x0 + 1) & mask;
    const int y1 = (y0 + 1) & mask;
    const float* r0 = m.ptr<float>(y0);
    const float* r1 = m.ptr<float>(y1);
    return (r0[x0] * (1 - as) + r0[x1] * as) * (1 - at) + (r1[x0] * (1 - as) + r1[x1] * as) * at;
}

float ProceduralTexture::bilinearClamp(const cv::Mat& m, double u, double v)
{
    const int n = m.cols;
    const double s = std::clamp(u * n - 0.5, 0.0, n - 1.0);
    const double t = std::clamp(v * n - 0.5, 0.0, n - 1.0);
    const int x0 = std::min(static_cast<int>(s), n - 2);
    const int y0 = std::min(static_cast<int>(t), n - 2);
    const auto as = static_cast<float>(s - x0);
    const auto at = static_cast<float>(t - y0);
    const float* r0 = m.ptr<float>(y0);
    const float* r1 = m.ptr<float>(y0 + 1);
    return (r0[x0] * (1 - as) + r0[x0 + 1] * as) * (1 - at) +
           (r1[x0] * (1 - as) + r1[x0 + 1] * as) * at;
}

float ProceduralTexture::sampleWrap(double s, double t) const
{
    return bilinearWrap(m_img, m_mask, s, t);
}

float ProceduralTexture::sampleClamp(double u, double v) const
{
    return bilinearClamp(m_img, u, v);
}

float ProceduralTexture::sampleWrapLod(double s, double t, double footprint) const
{
    if (footprint <= 1.0 || m_mips.empty())
    {
        return bilinearWrap(m_img, m_mask, s, t);
    }
    const double lod = std::min(std::log2(footprint), static_cast<double>(m_mips.size()));
    const int l0 = static_cast<int>(lod);
    const auto a = static_cast<float>(lod - l0);
    auto level = [&](int l)
    {
        if (l == 0)
        {
            return bilinearWrap(m_img, m_mask, s, t);
        }
        const cv::Mat& m = m_mips[static_cast<std::size_t>(l - 1)];
        const double k = 1.0 / static_cast<double>(1 << l);
        return bilinearWrap(m, m.cols - 1, s * k, t * k);
    };
    const float v0 = level(l0);
    if (a == 0.0F || l0 >= static_cast<int>(m_mips.size()))
    {
        return v0;
    }
    return v0 * (1 - a) + level(l0 + 1) * a;
}

float ProceduralTexture::sampleClampLod(double u, double v, double footprint) const
{
    if (footprint <= 1.0 || m_mips.empty())
    {
        return bilinearClamp(m_img, u, v);
    }
    const double lod = std::min(std::log2(footprint), static_cast<double>(m_mips.size()));
    const int l0 = static_cast<int>(lod);
    const auto a = static_cast<float>(lod - l0);
    auto level = [&](int l)
    { return bilinearClamp(l == 0 ? m_img : m_mips[static_cast<std::size_t>(l - 1)], u, v); };
    const float v0 = level(l0);
    if (a == 0.0F || l0 >= static_cast<int>(m_mips.size()))
    {
        return v0;
    }
    return v0 * (1 - a) + level(l0 + 1) * a;
}

}  // namespace emslam::sim
