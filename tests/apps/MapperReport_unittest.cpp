// SPDX-License-Identifier: BSD-3-Clause
#include "TestData.h"
#include "TestHelpers.h"

#include <emslam/apps/MapperReport.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <string>
#include <vector>

using emslam::apps::MapperReportData;
using mrpt::poses::CPose3D;

namespace
{
const std::vector<std::string> PLOT_IDS = {
    "plot-top",
    "plot-side",
    "plot-error-distance",
    "plot-error-distance-rotation",
    "plot-error-time",
    "plot-matches",
    "plot-points",
    "plot-energy-drop",
    "plot-energy",
    "plot-attempts",
    "plot-time"};

std::string readText(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::size_t countOf(const std::string& text, const std::string& what)
{
    std::size_t n = 0;
    for (auto p = text.find(what); p != std::string::npos; p = text.find(what, p + what.size()))
    {
        ++n;
    }
    return n;
}

/** `token` (lower case) anywhere in `text`, ignoring case, not inside a longer word. */
bool containsToken(const std::string& text, const std::string& token)
{
    std::string low(text.size(), ' ');
    for (std::size_t i = 0; i < text.size(); ++i)
    {
        low[i] = static_cast<char>(std::tolower(static_cast<unsigned char>(text[i])));
    }
    const auto letter = [&](std::size_t i)
    { return i < low.size() && std::isalpha(static_cast<unsigned char>(low[i])); };
    for (auto p = low.find(token); p != std::string::npos; p = low.find(token, p + 1))
    {
        if ((p == 0 || !letter(p - 1)) && !letter(p + token.size()))
        {
            return true;
        }
    }
    return false;
}

/** A 10 m x 10 m square driven on the floor (x-z plane), `n` poses. */
emslam::io::TumTrajectory square(std::size_t n, double scale, double height)
{
    emslam::io::TumTrajectory t;
    for (std::size_t i = 0; i < n; ++i)
    {
        const double s = 40.0 * static_cast<double>(i) / static_cast<double>(n);  // [0, 40) m
        const int side = static_cast<int>(s / 10.0);
        const double u = s - 10.0 * side;
        const double x[] = {u, 10.0, 10.0 - u, 0.0}, z[] = {0.0, u, 10.0, 10.0 - u};
        t.add(
            0.1 * static_cast<double>(i),
            CPose3D(scale * x[side], height, scale * z[side], 0, 0, 0));
    }
    return t;
}

MapperReportData syntheticData()
{
    MapperReportData d;
    d.title = "loop <A&B> \"test\"";
    d.ground_truth = square(200, 1.0, 0.0);
    d.egomotion = square(200, 1.08, -0.3);
    d.slam = square(200, 1.01, -0.05);
    for (std::size_t i = 0; i < 200; ++i)
    {
        emslam::slam::FrameRecord f;
        f.index = i;
        f.ms_stereo = 20.0 + static_cast<double>(i % 7);
        f.ms_egomotion = 8.0 + static_cast<double>(i % 5);
        f.ms_rectification = i % 40 == 39 ? 150.0 + static_cast<double>(i) : 0.0;
        f.points = 3000 + 10 * (i % 11);
        f.initial_matches = 400 + i % 13;
        f.final_matches = 250 + i % 9;
        d.frames.push_back(f);
    }
    double energy = 5000.0;
    for (std::size_t k = 0; k < 5; ++k)
    {
        emslam::rectify::RectificationStats r;
        r.attempts = 100 + 30 * k;
        r.energy_before = energy;
        for (std::size_t a = 0; a < r.attempts; ++a)
        {
            const bool success = a % 3 == 0;
            r.successes += success;
            r.failures += !success;
            energy -= success ? 2.0 : 0.0;
            r.energy_trace.push_back(static_cast<float>(energy + (success ? 0.0 : 1.5)));
        }
        r.energy_after = energy;
        energy += 120.0;  // new frames raise the energy before the next rectification
        d.rectifications.push_back(r);
    }
    d.summary = {{"frames", "200"}, {"ATE <rmse> & co", "0.12 m"}};
    const emslam::eval::TrajectoryMetrics::Options opts;
    d.egomotion_vs_gt = emslam::eval::TrajectoryMetrics::compute(d.ground_truth, d.egomotion, opts);
    d.slam_vs_gt = emslam::eval::TrajectoryMetrics::compute(d.ground_truth, d.slam, opts);
    return d;
}

/** Checks what every report must satisfy, whatever its data. */
void expectWellFormed(const std::string& html)
{
    for (const auto& id : PLOT_IDS)
    {
        EXPECT_NE(html.find("id=\"" + id + "\""), std::string::npos) << id;
    }
    EXPECT_NE(html.find("<table id=\"summary\">"), std::string::npos);
    EXPECT_EQ(countOf(html, "<svg"), PLOT_IDS.size());
    EXPECT_EQ(countOf(html, "</svg>"), PLOT_IDS.size());
    EXPECT_EQ(countOf(html, "<title>"), countOf(html, "</title>"));
    EXPECT_FALSE(containsToken(html, "nan"));
    EXPECT_FALSE(containsToken(html, "inf"));
    EXPECT_EQ(countOf(html, "http://"), PLOT_IDS.size());  // only the SVG namespace
    EXPECT_EQ(countOf(html, "xmlns=\"http://www.w3.org/2000/svg\""), PLOT_IDS.size());
    EXPECT_EQ(countOf(html, "https://"), 0u);
    EXPECT_EQ(html.find("<script"), std::string::npos);
}

/** The text of the element with `id`, up to its closing `</svg>`. */
std::string svgOf(const std::string& html, const std::string& id)
{
    const auto b = html.find("id=\"" + id + "\"");
    const auto e = html.find("</svg>", b);
    return b == std::string::npos || e == std::string::npos ? "" : html.substr(b, e - b);
}

/** The `d` attributes of all `<path>` elements of `svg`, concatenated. */
std::string pathData(const std::string& svg)
{
    std::string d;
    for (auto p = svg.find("<path"); p != std::string::npos; p = svg.find("<path", p + 1))
    {
        const auto b = svg.find(" d=\"", p) + 4;
        d += svg.substr(b, svg.find('"', b) - b);
    }
    return d;
}

/** The texts of `svg` centred under a point (x tick labels and the x axis label). */
std::vector<std::string> centredTexts(const std::string& svg)
{
    std::vector<std::string> t;
    const std::string tag = "text-anchor=\"middle\">";
    for (auto p = svg.find(tag); p != std::string::npos; p = svg.find(tag, p + 1))
    {
        const auto b = p + tag.size();
        t.push_back(svg.substr(b, svg.find('<', b) - b));
    }
    return t;
}

/** A small grey PNG, as the mapper's map_top.png. */
void writeMapPicture(const std::string& file)
{
    cv::Mat img(120, 160, CV_8UC3, cv::Scalar(200, 200, 200));
    cv::rectangle(img, {20, 20}, {140, 100}, cv::Scalar(20, 120, 20), 3);
    ASSERT_TRUE(cv::imwrite(file, img)) << file;
}

/** Runs chromium headless with `args` (60 s at most); returns its exit status
 * and leaves its console output in `log`. */
int runChromium(const std::string& tmp, const std::string& args, const std::string& log)
{
    static int runs = 0;
    const std::string profile = tmp + "/profile_" + std::to_string(++runs);
    const std::string cmd =
        "timeout 60 /usr/bin/chromium --headless --no-sandbox --disable-gpu --disable-quic "
        "--no-first-run --disable-background-networking --disable-component-update "
        "--disable-sync --user-data-dir='" +
        profile + "' " + args + " 2>'" + log + "'";
    return std::system(cmd.c_str());
}
}  // namespace

TEST(MapperReport, syntheticLoopHasEveryPlotAndIsSelfContained)
{
    const std::string dir = emslam::test::makeTempDir("report_synth");
    const std::string file = dir + "/report.html";
    emslam::apps::writeMapperReport(file, syntheticData());
    const std::string html = readText(file);
    expectWellFormed(html);
    EXPECT_FALSE(std::filesystem::exists(file + ".partial"));
    EXPECT_LT(html.size(), 200u * 1024u);

    // Escaped title and summary; the raw text never appears.
    EXPECT_NE(html.find("loop &lt;A&amp;B&gt; &quot;test&quot;"), std::string::npos);
    EXPECT_EQ(html.find("<A&B>"), std::string::npos);
    EXPECT_NE(html.find("ATE &lt;rmse&gt; &amp; co"), std::string::npos);

    // Three trajectories in both views, with start circles and end squares.
    for (const std::string id : {"plot-top", "plot-side"})
    {
        const std::string svg = svgOf(html, id);
        EXPECT_EQ(countOf(svg, "<polyline"), 3u) << id;
        EXPECT_GE(countOf(svg, "<circle"), 3u) << id;
        EXPECT_NE(svg.find("stroke-dasharray"), std::string::npos) << id;
        EXPECT_NE(svg.find("[m]"), std::string::npos) << id;
    }
    EXPECT_EQ(countOf(svgOf(html, "plot-energy"), "<circle"), 5u + 1u);  // 5 starts + legend
    EXPECT_EQ(countOf(svgOf(html, "plot-attempts"), "<path"), 2u);
    EXPECT_EQ(countOf(pathData(svgOf(html, "plot-attempts")), "M"), 2u * 5u);  // 5 bars each
    EXPECT_NE(svgOf(html, "plot-time").find("time [ms]"), std::string::npos);
}

TEST(MapperReport, topViewKeepsEqualAspect)
{
    // A zigzag over x in [0, 20] m, z in [0, 10] m; with 5 % margins the plot
    // area (704 px wide) spans 22 m x 11 m, so it is 352 px high.
    MapperReportData d;
    for (int i = 0; i <= 20; ++i)
    {
        d.slam.add(i, CPose3D(i, 0, i % 2 == 0 ? 0.0 : 10.0, 0, 0, 0));
    }
    const std::string dir = emslam::test::makeTempDir("report_aspect");
    emslam::apps::writeMapperReport(dir + "/r.html", d);
    const std::string svg = svgOf(readText(dir + "/r.html"), "plot-top");
    const auto h = svg.find("height=\"");
    ASSERT_NE(h, std::string::npos);
    EXPECT_NEAR(std::stod(svg.substr(h + 8)), 352.0 + 108.0, 1.0);  // plus title and axes

    // The first step, 1 m along x and 10 m along z, has the same px per metre.
    const auto p = svg.find("points=\"");
    ASSERT_NE(p, std::string::npos);
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    ASSERT_EQ(std::sscanf(svg.c_str() + p + 8, "%lf,%lf %lf,%lf", &x0, &y0, &x1, &y1), 4);
    EXPECT_NEAR((x1 - x0) * 10.0, y0 - y1, 0.2);
}

TEST(MapperReport, emptyDataStillGivesAValidReport)
{
    const std::string dir = emslam::test::makeTempDir("report_empty");
    const std::string file = dir + "/report.html";
    emslam::apps::writeMapperReport(file, MapperReportData{});
    const std::string html = readText(file);
    expectWellFormed(html);
    EXPECT_NE(html.find("no rectification ran"), std::string::npos);
    EXPECT_NE(html.find("no data"), std::string::npos);
}

TEST(MapperReport, degenerateValuesGiveFiniteCoordinates)
{
    MapperReportData d;
    d.egomotion.add(0, CPose3D(1, 1, 1, 0, 0, 0));  // one pose: zero extent
    d.slam.add(0, CPose3D(1, 1, 1, 0, 0, 0));
    d.frames.resize(3);  // all times zero
    emslam::rectify::RectificationStats constant, broken, untraced;
    constant.energy_trace.assign(10, 7.0f);
    broken.energy_trace = {
        std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(), 3.0f};
    untraced.attempts = 4;
    untraced.energy_before = 9.0;
    untraced.energy_after = 8.0;
    d.rectifications = {constant, broken, untraced};
    const std::string dir = emslam::test::makeTempDir("report_degenerate");
    emslam::apps::writeMapperReport(dir + "/r.html", d);
    expectWellFormed(readText(dir + "/r.html"));
}

TEST(MapperReport, largeInputsAreDecimatedButKeepTheirPeaks)
{
    MapperReportData d = syntheticData();
    d.egomotion = square(50000, 1.0, 0.0);
    d.frames.assign(50000, emslam::slam::FrameRecord{});
    for (std::size_t i = 0; i < d.frames.size(); ++i)
    {
        d.frames[i].index = i;
        d.frames[i].ms_stereo = 10.0;
    }
    d.frames[31234].ms_rectification = 1000.0;  // a lone peak
    d.rectifications.assign(3000, d.rectifications.front());
    const std::string dir = emslam::test::makeTempDir("report_large");
    emslam::apps::writeMapperReport(dir + "/r.html", d);
    const std::string html = readText(dir + "/r.html");
    expectWellFormed(html);
    EXPECT_LT(html.size(), 1500u * 1024u);

    // The peak (1000 ms of a 1050 ms axis) is drawn near the top of the plot
    // area, which starts at y = 56 px.
    const std::string svg = svgOf(html, "plot-time");
    const auto p = svg.find("points=\"");
    ASSERT_NE(p, std::string::npos);
    std::istringstream pts(svg.substr(p + 8, svg.find('"', p + 8) - p - 8));
    double top = 1e9, x = 0, y = 0;
    char comma = 0;
    while (pts >> x >> comma >> y)
    {
        top = std::min(top, y);
    }
    EXPECT_LT(top, 70.0);
}

TEST(MapperReport, unwritablePathThrowsNamingIt)
{
    const std::string file =
        emslam::test::makeTempDir("report_unwritable") + "/no/such/folder/report.html";
    emslam::test::expectThrowContaining(
        [&] { emslam::apps::writeMapperReport(file, MapperReportData{}); }, {file});
}

TEST(MapperReport, errorPlotsDrawEgomotionAndSlamAgainstTheGroundTruth)
{
    const std::string dir = emslam::test::makeTempDir("report_errors");
    emslam::apps::writeMapperReport(dir + "/report.html", syntheticData());
    const std::string html = readText(dir + "/report.html");
    // 40 m square: segments of 2, 4, ..., 16 m; one curve with a dot per length each.
    for (const std::string id : {"plot-error-distance", "plot-error-distance-rotation"})
    {
        const std::string svg = svgOf(html, id);
        EXPECT_EQ(countOf(svg, "<polyline"), 2u) << id;
        EXPECT_EQ(countOf(svg, "<circle"), 2u * 8u) << id;
        EXPECT_NE(svg.find("segment length [m]"), std::string::npos) << id;
    }
    EXPECT_NE(svgOf(html, "plot-error-distance").find("translation error [%]"), std::string::npos);
    EXPECT_EQ(countOf(svgOf(html, "plot-error-time"), "<polyline"), 2u);
    EXPECT_EQ(countOf(svgOf(html, "plot-matches"), "<polyline"), 2u);
    EXPECT_NE(svgOf(html, "plot-matches").find("LWO inliers"), std::string::npos);
    EXPECT_EQ(countOf(svgOf(html, "plot-points"), "<polyline"), 1u);
    // Five rectifications, each lowering the energy: five green drop bars, no rise.
    const std::string drop = svgOf(html, "plot-energy-drop");
    ASSERT_EQ(countOf(drop, "<path"), 2u);
    EXPECT_EQ(countOf(pathData(drop), "M"), 5u);

    // Without ground truth the error plots say so instead of drawing.
    MapperReportData no_gt = syntheticData();
    no_gt.egomotion_vs_gt.reset();
    no_gt.slam_vs_gt.reset();
    emslam::apps::writeMapperReport(dir + "/no_gt.html", no_gt);
    const std::string plain = readText(dir + "/no_gt.html");
    expectWellFormed(plain);
    EXPECT_EQ(countOf(svgOf(plain, "plot-error-time"), "<polyline"), 0u);
    EXPECT_NE(svgOf(plain, "plot-error-distance").find("no ground truth"), std::string::npos);
}

TEST(MapperReport, countAxesHaveIntegerTicks)
{
    // Two rectifications and three frames: a 1-2-5 tick step would be 0.2 or 0.5.
    MapperReportData d = syntheticData();
    d.rectifications.resize(2);
    d.frames.resize(3);
    const std::string dir = emslam::test::makeTempDir("report_ticks");
    emslam::apps::writeMapperReport(dir + "/r.html", d);
    const std::string html = readText(dir + "/r.html");
    for (const std::string id :
         {"plot-attempts", "plot-energy-drop", "plot-time", "plot-matches", "plot-points"})
    {
        std::size_t ticks = 0;
        for (const auto& label : centredTexts(svgOf(html, id)))
        {
            if (!label.empty() && (std::isdigit(static_cast<unsigned char>(label[0])) != 0))
            {
                EXPECT_EQ(label.find('.'), std::string::npos) << id << " tick " << label;
                ++ticks;
            }
        }
        EXPECT_GE(ticks, 2u) << id;
    }
}

TEST(MapperReport, embedsTheMapPictureAndLinksEveryFileOfItsFolder)
{
    const std::string dir = emslam::test::makeTempDir("report_links");
    for (const std::string name :
         {"trajectory_egomotion.tum", "trajectory_slam.tum", "map.ply", "map.3Dscene",
          "entropy_map.bin", "stats.csv", "summary.json", "effective.ini", "extra notes.txt",
          "stats.csv.partial"})
    {
        std::ofstream(dir + "/" + name) << "x\n";
    }
    emslam::apps::writeMapperReport(dir + "/report.html", syntheticData());
    std::string html = readText(dir + "/report.html");
    EXPECT_NE(html.find("id=\"map-missing\""), std::string::npos);  // not written yet
    EXPECT_EQ(html.find("<img"), std::string::npos);

    writeMapPicture(dir + "/map_top.png");
    emslam::apps::writeMapperReport(dir + "/report.html", syntheticData());
    html = readText(dir + "/report.html");
    EXPECT_NE(html.find("<img id=\"map-top\" src=\"map_top.png\" alt=\""), std::string::npos);
    for (const std::string name :
         {"trajectory_egomotion.tum", "trajectory_slam.tum", "map.ply", "map.3Dscene",
          "map_top.png", "entropy_map.bin", "stats.csv", "summary.json", "effective.ini"})
    {
        EXPECT_EQ(countOf(html, "<a href=\"" + name + "\">"), 1u) << name;
    }
    EXPECT_NE(html.find("<a href=\"extra%20notes.txt\">extra notes.txt</a>"), std::string::npos);
    EXPECT_EQ(html.find(".partial"), std::string::npos);
    EXPECT_EQ(html.find("href=\"report.html\""), std::string::npos);
    EXPECT_LT(html.find("trajectory_slam.tum"), html.find("effective.ini"));  // fixed order
}

TEST(MapperReport, headlessChromiumRendersThePlots)
{
    if (!std::filesystem::exists("/usr/bin/chromium"))
    {
        GTEST_SKIP() << "/usr/bin/chromium not found (Debian package 'chromium')";
    }
    const std::string dir = emslam::test::makeTempDir("report_chromium");
    const std::string file = dir + "/report.html";
    writeMapPicture(dir + "/map_top.png");
    emslam::apps::writeMapperReport(file, syntheticData());

    const std::string dom = dir + "/dom.html", log1 = dir + "/dump.log";
    const int rc1 = runChromium(dir, "--dump-dom 'file://" + file + "' >'" + dom + "'", log1);
    ASSERT_EQ(rc1, 0) << "chromium --dump-dom failed:\n" << readText(log1);
    const std::string html = readText(dom);
    for (const auto& id : PLOT_IDS)
    {
        const std::string svg = svgOf(html, id);
        EXPECT_GE(countOf(svg, "<polyline") + countOf(svg, "<path"), 1u)
            << id << " has no curve in the DOM; chromium said:\n"
            << readText(log1);
    }
    EXPECT_GE(countOf(html, "<polyline") + countOf(html, "<path"), 8u);
    // The new plots carry curves in the rendered DOM, and the map picture is there.
    for (const std::string id : {"plot-error-distance", "plot-error-time", "plot-matches"})
    {
        EXPECT_GE(countOf(svgOf(html, id), "<polyline"), 2u) << id;
    }
    EXPECT_GE(countOf(pathData(svgOf(html, "plot-energy-drop")), "M"), 5u);
    EXPECT_NE(html.find("id=\"map-top\""), std::string::npos);
    EXPECT_NE(html.find("src=\"map_top.png\""), std::string::npos);
    EXPECT_NE(html.find("<ul id=\"outputs\">"), std::string::npos);

    const std::string png = dir + "/report.png", log2 = dir + "/screenshot.log";
    const int rc2 = runChromium(
        dir, "--screenshot='" + png + "' --window-size=1280,2400 'file://" + file + "'", log2);
    ASSERT_EQ(rc2, 0) << "chromium --screenshot failed:\n" << readText(log2);
    ASSERT_TRUE(std::filesystem::exists(png)) << readText(log2);
    EXPECT_GT(std::filesystem::file_size(png), 10u * 1024u);
    const cv::Mat img = cv::imread(png, cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(img.empty()) << png;
    cv::Scalar mean, stddev;
    cv::meanStdDev(img, mean, stddev);
    EXPECT_GT(stddev[0], 10.0) << "the screenshot is nearly one colour: " << png;
}
