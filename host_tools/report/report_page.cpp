// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/report/report_page.hpp"

#include "algorithms/io/file_util.hpp"
#include "algorithms/io/sha256.hpp"
#include "host_tools/report/report_assets.hpp"

namespace bimslam::report {

namespace {

// Replaces the first "/*@name@*/" of the template.
void Inline(std::string& page, const std::string& name, const std::string& content) {
    const std::string token = "/*@" + name + "@*/";
    const size_t at = page.find(token);
    if (at != std::string::npos) page.replace(at, token.size(), content);
}

}  // namespace

std::string BuildPage(const nlohmann::json& data) {
    std::string page = ReportAsset("report.html");
    // Data first: the assets inlined after it cannot then be mistaken for the data's token.
    std::string text = data.dump();
    // "</" would end the <script> element early; "<\/" is the same JSON string.
    for (size_t at = text.find("</"); at != std::string::npos; at = text.find("</", at + 3)) {
        text.replace(at, 2, "<\\/");
    }
    Inline(page, "DATA", text);
    for (const char* name : {"report.css", "three.min.js", "OrbitControls.js", "report_visits.js", "report.js"}) {
        Inline(page, name, ReportAsset(name));
    }
    return page;
}

void WriteReport(const std::filesystem::path& out, const std::filesystem::path& html,
                 const ReportProgress& progress, const ReportConfig& config) {
    const nlohmann::json data = CollectReportData(out, config, progress);
    if (progress) progress("writing " + html.string(), 1.0);
    io::WriteFileAtomic(html, BuildPage(data));
}

std::string PageVersion() {
    std::string all;
    for (const std::string& name : ReportAssetNames()) all += name + "\n" + ReportAsset(name);
    return io::Sha256Hex(all);
}

}  // namespace bimslam::report
