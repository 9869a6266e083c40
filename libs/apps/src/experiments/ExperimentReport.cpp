// SPDX-License-Identifier: BSD-3-Clause
#include <emslam/apps/ExperimentReport.h>
#include <emslam/apps/SvgPlot.h>
#include <emslam/io/AtomicTextFile.h>
#include <emslam/io/Json.h>

#include <mrpt/core/bits_math.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <set>
#include <sstream>

namespace emslam::apps
{
namespace
{
using Getter = std::function<double(const ExperimentResult&)>;

/** One numeric column, the same in the three files. */
struct Column
{
    std::string header;  //!< Markdown / HTML header
    std::string key;     //!< JSON key
    int decimals;
    Getter value;
};

const std::vector<Column>& columns()
{
    using R = ExperimentResult;
    static const std::vector<Column> c{
        {"path [m]", "path_m", 1, [](const R& r) { return r.path_m; }},
        {"obs.", "observations", 0, [](const R& r) { return double(r.observations); }},
        {"frames", "frames", 0, [](const R& r) { return double(r.frames); }},
        {"ego fails", "egomotion_failures", 0,
         [](const R& r) { return double(r.egomotion_failures); }},
        {"ego gap [m]", "egomotion_gap_m", 3, [](const R& r) { return r.egomotion_gap_m; }},
        {"ego gap %", "egomotion_gap_percent", 2,
         [](const R& r) { return r.egomotionGapPercent(); }},
        {"SLAM gap [m]", "slam_gap_m", 3, [](const R& r) { return r.slam_gap_m; }},
        {"SLAM gap %", "slam_gap_percent", 2, [](const R& r) { return r.slamGapPercent(); }},
        {"ego/SLAM gap", "gap_ratio", 1,
         [](const R& r) { return r.slam_gap_m > 0 ? r.egomotion_gap_m / r.slam_gap_m : NAN; }},
        {"ego ATE [m]", "egomotion_ate_m", 3, [](const R& r) { return r.egomotion_ate_m; }},
        {"SLAM ATE [m]", "slam_ate_m", 3, [](const R& r) { return r.slam_ate_m; }},
        {"ego map med. [m]", "egomotion_map_median_m", 3,
         [](const R& r) { return r.egomotion_map_median_m; }},
        {"ego map p90 [m]", "egomotion_map_p90_m", 3,
         [](const R& r) { return r.egomotion_map_p90_m; }},
        {"ego map compl.", "egomotion_map_completeness", 3,
         [](const R& r) { return r.egomotion_map_completeness; }},
        {"SLAM map med. [m]", "slam_map_median_m", 3,
         [](const R& r) { return r.slam_map_median_m; }},
        {"SLAM map p90 [m]", "slam_map_p90_m", 3, [](const R& r) { return r.slam_map_p90_m; }},
        {"SLAM map compl.", "slam_map_completeness", 3,
         [](const R& r) { return r.slam_map_completeness; }},
        {"paper path [m]", "paper_path_m", 1, [](const R& r) { return r.paper_path_m; }},
        {"paper obs.", "paper_observations", 0, [](const R& r) { return r.paper_observations; }},
        {"paper ego gap [m]", "paper_egomotion_gap_m", 2,
         [](const R& r) { return r.paper_egomotion_gap_m; }},
        {"paper SLAM gap [m]", "paper_slam_gap_m", 2,
         [](const R& r) { return r.paper_slam_gap_m; }},
        {"ms stereo", "ms_stereo", 1, [](const R& r) { return r.ms_stereo; }},
        {"ms ego", "ms_egomotion", 1, [](const R& r) { return r.ms_egomotion; }},
        {"rect. calls", "rectifications", 0, [](const R& r) { return double(r.rectifications); }},
        {"ms/call med.", "rect_median_ms", 0, [](const R& r) { return r.rect_median_ms; }},
        {"ms/call max", "rect_max_ms", 0, [](const R& r) { return r.rect_max_ms; }},
        {"attempts", "attempts", 0, [](const R& r) { return double(r.attempts); }},
        {"successes", "successes", 0, [](const R& r) { return double(r.successes); }},
        {"H truth", "entropy_truth", 3, [](const R& r) { return r.entropy_truth; }},
        {"H ego", "entropy_egomotion", 3, [](const R& r) { return r.entropy_egomotion; }},
        {"H SLAM", "entropy_slam", 3, [](const R& r) { return r.entropy_slam; }},
        {"H rect. (before LC)", "entropy_rectified", 3,
         [](const R& r) { return r.entropy_rectified; }},
        {"H phase spread", "entropy_phase_spread", 3,
         [](const R& r) { return r.entropy_phase_spread; }},
        {"scan at truth", "scan_fraction_at_truth", 2,
         [](const R& r) { return r.energy_scan ? r.energy_scan->fraction_at_truth : NAN; }},
        {"scan argmin t [m]", "scan_median_abs_argmin_m", 3,
         [](const R& r)
         { return r.energy_scan ? r.energy_scan->median_abs_argmin_translation_m : NAN; }},
        {"scan argmin rot [deg]", "scan_median_abs_argmin_deg", 1,
         [](const R& r) {
             return r.energy_scan ? mrpt::RAD2DEG(r.energy_scan->median_abs_argmin_rotation_rad)
                                  : NAN;
         }},
        {"run [s]", "seconds", 0, [](const R& r) { return r.seconds; }},
    };
    return c;
}

std::string cell(double v, int decimals)
{
    if (!std::isfinite(v))
    {
        return "–";
    }
    char buf[64];
    std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
    return buf;
}

/** A table row: a run, or the median of a group of runs over their seeds. */
struct Row
{
    const ExperimentResult* first;  //!< names and paper figures
    std::string seed;               //!< "3", or "median (3 seeds)"
    std::vector<double> values;     //!< one per column
    bool median{false};
};

double median(std::vector<double> v)
{
    v.erase(
        std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
    if (v.empty())
    {
        return std::numeric_limits<double>::quiet_NaN();
    }
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/** Runs in order; after the runs of one experiment and energy, their median. */
std::vector<Row> tableRows(const std::vector<ExperimentResult>& results)
{
    std::vector<Row> rows;
    std::size_t i = 0;
    while (i < results.size())
    {
        std::size_t j = i;
        while (j < results.size() && results[j].experiment == results[i].experiment &&
               results[j].mapper == results[i].mapper && results[j].variant == results[i].variant)
        {
            Row r{&results[j], std::to_string(results[j].seed), {}};
            if (results[j].interrupted)
            {
                r.seed += " (partial)";
            }
            for (const auto& c : columns())
            {
                r.values.push_back(c.value(results[j]));
            }
            rows.push_back(r);
            ++j;
        }
        if (j - i > 1)
        {
            Row m{&results[i], "median (" + std::to_string(j - i) + " seeds)", {}, true};
            for (std::size_t c = 0; c < columns().size(); ++c)
            {
                std::vector<double> v;
                for (std::size_t k = i; k < j; ++k)
                {
                    v.push_back(rows[rows.size() - (j - i) + (k - i)].values[c]);
                }
                m.values.push_back(median(v));
            }
            rows.push_back(m);
        }
        i = j;
    }
    return rows;
}

std::string experimentName(const ExperimentResult& r)
{
    return r.experiment + (r.loop ? "" : " (open)");
}

/** A variant column only when the runs have named variants. */
bool withVariants(const std::vector<Row>& rows)
{
    return std::any_of(
        rows.begin(), rows.end(), [](const Row& r) { return !r.first->variant.empty(); });
}

std::string markdown(const std::vector<Row>& rows, const ExperimentReportInfo& info)
{
    const bool variants = withVariants(rows);
    std::ostringstream s;
    s << "# emslam: the paper's experiments\n\n"
      << "Made by `" << info.command << "`"
      << (info.quick ? " (--quick: partial trajectories)" : "")
      << (info.exact_depth ? " (--exact-depth: the renderer's exact depth instead of stereo)" : "")
      << (info.interrupted ? " (interrupted: the finished runs only)" : "") << " in "
      << cell(info.seconds / 60.0, 1) << " min.\n\n"
      << "Gaps are the end-point error once the trajectory is anchored to the ground truth "
         "at its first pose: on a loop (the ground truth returns to its start) that is the "
         "paper's loop gap, the distance between the first and last poses; on an open path "
         "(marked) it is the end error. ATE: RMSE after SE(3) alignment. Map columns: the map "
         "cloud, moved by its trajectory's SE(3) alignment, against the true surfaces the frames "
         "saw within the mapper's stereo range "
         "(emslam-eval --map): median and 90th percentile of the distance of its points to "
         "them, and completeness, the share of the surfaces within 5 cm of a map point; "
         "ego: the same keyframe clouds placed by the egomotion. H: the paper's "
         "entropy of the final map's elements placed by the ground truth, the egomotion and "
         "SLAM; H phase spread: how much H of the true map changes when the whole map moves by "
         "1/4, 1/2 or 3/4 of a cell (same geometry, another grid phase). Scan columns "
         "(--energy-scan): the fraction of scanned lines (one action perturbed along one "
         "dimension around the truth) whose minimum is at the truth, and the median |offset| of "
         "the minimum over the translation and the rotation lines (runs/.../energy_scan.csv "
         "has every line). H rect. (before LC): the same entropy at the rectifier's element "
         "poses, before loop closing moved them. Paper figures: Sáez & Escolano, §3 (– where "
         "the paper gives none).\n\n"
      << "| experiment | energy |" << (variants ? " variant |" : "") << " seed |";
    for (const auto& c : columns())
    {
        s << ' ' << c.header << " |";
    }
    s << "\n|---|---|" << (variants ? "---|" : "") << "---|";
    for (std::size_t c = 0; c < columns().size(); ++c)
    {
        s << "---:|";
    }
    s << '\n';
    for (const auto& r : rows)
    {
        const std::string b = r.median ? "**" : "";
        s << "| " << b << experimentName(*r.first) << b << " | " << b << r.first->label << " ("
          << r.first->energy << ")" << b << " | ";
        if (variants)
        {
            s << b << r.first->variant << b << " | ";
        }
        s << b << r.seed << b << " |";
        for (std::size_t c = 0; c < columns().size(); ++c)
        {
            s << ' ' << b << cell(r.values[c], columns()[c].decimals) << b << " |";
        }
        s << '\n';
    }
    return s.str();
}

std::string json(const std::vector<Row>& rows, const ExperimentReportInfo& info)
{
    std::ostringstream s;
    s << "{\n  \"command\": " << io::jsonString(info.command)
      << ",\n  \"suite\": " << io::jsonString(info.suite_file)
      << ",\n  \"quick\": " << (info.quick ? "true" : "false")
      << ",\n  \"exact_depth\": " << (info.exact_depth ? "true" : "false")
      << ",\n  \"interrupted\": " << (info.interrupted ? "true" : "false")
      << ",\n  \"seconds\": " << io::jsonNumber(info.seconds) << ",\n  \"runs\": [";
    bool first = true;
    for (const bool want_median : {false, true})
    {
        if (want_median)
        {
            s << "\n  ],\n  \"medians\": [";
            first = true;
        }
        for (const auto& r : rows)
        {
            if (r.median != want_median)
            {
                continue;
            }
            s << (first ? "" : ",")
              << "\n    {\"experiment\": " << io::jsonString(r.first->experiment)
              << ", \"loop\": " << (r.first->loop ? "true" : "false")
              << ", \"mapper\": " << io::jsonString(r.first->mapper)
              << ", \"energy\": " << io::jsonString(r.first->energy)
              << ", \"label\": " << io::jsonString(r.first->label)
              << ", \"variant\": " << io::jsonString(r.first->variant);
            if (r.median)
            {
                s << ", \"seeds\": " << io::jsonString(r.seed);
            }
            else
            {
                s << ", \"seed\": " << r.first->seed
                  << ", \"interrupted\": " << (r.first->interrupted ? "true" : "false");
            }
            for (std::size_t c = 0; c < columns().size(); ++c)
            {
                s << ", " << io::jsonString(columns()[c].key) << ": "
                  << io::jsonNumber(r.values[c]);
            }
            s << '}';
            first = false;
        }
    }
    s << "\n  ]\n}\n";
    return s.str();
}

std::string topViews(const std::vector<ExperimentResult>& results)
{
    using namespace emslam::apps::svg;
    std::ostringstream s;
    std::set<std::string> shown;  // experiment/mapper already drawn (first seed only)
    std::string current;
    for (const auto& r : results)
    {
        const std::string id = r.experiment + "/" + r.mapper + "/" + r.variant;
        if (!shown.insert(id).second)
        {
            continue;
        }
        if (r.experiment != current)
        {
            s << (current.empty() ? "" : "</div>\n") << "<h2>" << escapeHtml(r.title)
              << (r.figure.empty() ? "" : " — paper " + escapeHtml(r.figure)) << "</h2>\n"
              << "<div class=\"views\">\n";
            current = r.experiment;
        }
        const std::vector<TrajectoryTrack> tracks{
            {&r.ground_truth, "ground truth", GT_COLOUR, "6,4"},
            {&r.egomotion, "egomotion", EGO_COLOUR, ""},
            {&r.slam, "SLAM", SLAM_COLOUR, ""}};
        const std::string title =
            r.label + " (" + r.energy + ")" + (r.variant.empty() ? "" : ", " + r.variant) +
            ", seed " + std::to_string(r.seed) + (r.loop ? ": gap " : ": end error ") +
            cell(r.egomotion_gap_m, 2) + " m → " + cell(r.slam_gap_m, 2) + " m";
        s << trajectoryPlot(
            tracks,
            "top-" + r.experiment + "-" + r.energy + (r.variant.empty() ? "" : "-" + r.variant),
            title, topViewProjection, "x [m]", "z [m]", 240, 560);
    }
    if (!current.empty())
    {
        s << "</div>\n";
    }
    return s.str();
}

std::string html(
    const std::vector<Row>& rows,
    const std::vector<ExperimentResult>& results,
    const ExperimentReportInfo& info)
{
    using emslam::apps::svg::escapeHtml;
    const bool variants = withVariants(rows);
    std::ostringstream s;
    s << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
      << "<title>emslam: the paper's experiments</title>\n<style>"
      << "body{font-family:sans-serif;margin:1em 2em;color:#222}"
      << "table{border-collapse:collapse;font-size:12px}"
      << "th,td{border:1px solid #ccc;padding:2px 5px;text-align:right}"
      << "th{background:#f3f3f3;position:sticky;top:0}td.l{text-align:left}"
      << "tr.median td{font-weight:bold;background:#f7f7ff}"
      << ".views{display:flex;flex-wrap:wrap;gap:8px}.views "
         "svg{width:48%;min-width:420px;height:auto}"
      << "svg text{font-size:12px}svg .ttl{font-size:14px;font-weight:bold}"
      << "svg .grid{stroke:#e5e5e5}svg .frame{fill:none;stroke:#999}"
      << "</style></head><body>\n<h1>emslam: the paper's experiments</h1>\n<p>Made by <code>"
      << escapeHtml(info.command) << "</code>"
      << (info.quick ? " (--quick: partial trajectories)" : "")
      << (info.exact_depth ? " (--exact-depth: the renderer's exact depth instead of stereo)" : "")
      << (info.interrupted ? " (interrupted: the finished runs only)" : "") << " in "
      << cell(info.seconds / 60.0, 1)
      << " min. Gaps: end-point error after anchoring at the first pose (the loop gap on "
         "a loop); ATE after SE(3) alignment; map: distance of the map points, moved by that "
         "alignment, to the true "
         "surfaces (median, 90th percentile) and the share of the surfaces within 5 cm of the "
         "map; H: the paper's entropy of the final map at "
         "the ground truth, the egomotion and SLAM.</p>\n<table id=\"experiments\">\n<tr>"
      << "<th>experiment</th><th>energy</th>" << (variants ? "<th>variant</th>" : "")
      << "<th>seed</th>";
    for (const auto& c : columns())
    {
        s << "<th>" << escapeHtml(c.header) << "</th>";
    }
    s << "</tr>\n";
    for (const auto& r : rows)
    {
        s << "<tr" << (r.median ? " class=\"median\"" : "") << "><td class=\"l\">"
          << escapeHtml(experimentName(*r.first)) << "</td><td class=\"l\">"
          << escapeHtml(r.first->label + " (" + r.first->energy + ")") << "</td>";
        if (variants)
        {
            s << "<td class=\"l\">" << escapeHtml(r.first->variant) << "</td>";
        }
        s << "<td class=\"l\">" << escapeHtml(r.seed) << "</td>";
        for (std::size_t c = 0; c < columns().size(); ++c)
        {
            s << "<td>" << cell(r.values[c], columns()[c].decimals) << "</td>";
        }
        s << "</tr>\n";
    }
    s << "</table>\n<p>Top views (X-Z plane, metres): ground truth (dashed), egomotion (red), "
         "SLAM (green); ○ start, □ end.</p>\n"
      << topViews(results) << "</body></html>\n";
    return s.str();
}
}  // namespace

std::vector<std::string> experimentColumnKeys()
{
    std::vector<std::string> keys;
    for (const auto& c : columns())
    {
        keys.push_back(c.key);
    }
    return keys;
}

void writeExperimentReports(
    const std::string& dir,
    const std::vector<ExperimentResult>& results,
    const ExperimentReportInfo& info)
{
    const auto rows = tableRows(results);
    io::writeTextAtomically(dir + "/experiments.md", markdown(rows, info));
    io::writeTextAtomically(dir + "/experiments.json", json(rows, info));
    io::writeTextAtomically(dir + "/experiments.html", html(rows, results, info));
}

}  // namespace emslam::apps
