// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/changes/step_index.hpp"

#include <cctype>
#include <charconv>

#include "algorithms/common/status.hpp"

namespace bimslam::change_detection {
namespace {

std::string_view Trim(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
    return s;
}

std::string Upper(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = char(std::toupper(static_cast<unsigned char>(c)));
    return out;
}

}  // namespace

StepIndex::StepIndex(const std::string& name, std::string_view text) {
    const size_t first_newline = text.find('\n');
    if (first_newline != std::string_view::npos && first_newline > 0 &&
        text[first_newline - 1] == '\r') {
        newline_ = "\r\n";
    }
    bool in_data = false;
    bool closed = false;
    size_t start = 0;  // of the current statement
    for (size_t i = 0; i < text.size() && !closed; ++i) {
        const char c = text[i];
        if (c == '\'') {  // a string: '' is an escaped quote
            for (++i; i < text.size(); ++i) {
                if (text[i] != '\'') continue;
                if (i + 1 < text.size() && text[i + 1] == '\'') {
                    ++i;
                    continue;
                }
                break;
            }
            continue;
        }
        if (c == '/' && i + 1 < text.size() && text[i + 1] == '*') {
            const size_t end = text.find("*/", i + 2);
            i = end == std::string_view::npos ? text.size() : end + 1;
            continue;
        }
        if (c != ';') continue;
        std::string_view statement = Trim(text.substr(start, i - start));
        // Comments before the statement.
        while (statement.starts_with("/*")) {
            const size_t end = statement.find("*/");
            statement = Trim(end == std::string_view::npos ? std::string_view{}
                                                           : statement.substr(end + 2));
        }
        const size_t statement_start = size_t(statement.data() - text.data());
        start = i + 1;
        if (!in_data) {
            in_data = Upper(statement) == "DATA";
            continue;
        }
        if (Upper(statement) == "ENDSEC") {
            data_end_ = statement_start;
            closed = true;
            break;
        }
        if (statement.empty() || statement.front() != '#') continue;
        const size_t eq = statement.find('=');
        const size_t open = statement.find('(');
        if (eq == std::string_view::npos || open == std::string_view::npos || open < eq ||
            statement.back() != ')') {
            continue;  // not an entity instance we understand; left as it is
        }
        StepEntity e;
        const std::string_view id_text = Trim(statement.substr(1, eq - 1));
        const auto [end, ec] =
            std::from_chars(id_text.data(), id_text.data() + id_text.size(), e.id);
        if (ec != std::errc{} || end != id_text.data() + id_text.size()) continue;
        e.type = Upper(Trim(statement.substr(eq + 1, open - eq - 1)));
        e.args = statement.substr(open + 1, statement.size() - open - 2);
        const std::vector<std::string_view> args = SplitArgs(e.args);
        if (!args.empty() && args[0].size() >= 2 && args[0].front() == '\'' &&
            args[0].back() == '\'') {
            e.global_id = std::string(args[0].substr(1, args[0].size() - 2));
        }
        max_id_ = std::max(max_id_, e.id);
        if (!e.global_id.empty()) by_global_id_.emplace(e.global_id, entities_.size());
        entities_.push_back(std::move(e));
    }
    if (!in_data) {
        throw common::FileError(common::StatusCode::kParseError, name, 0,
                                "no DATA section: not an ISO-10303-21 IFC file");
    }
    if (!closed) {
        throw common::FileError(common::StatusCode::kDataLoss, name, 0,
                                "the DATA section is not closed by ENDSEC (cut off?)");
    }
}

const StepEntity* StepIndex::FindGlobalId(const std::string& global_id) const {
    const auto it = by_global_id_.find(global_id);
    return it == by_global_id_.end() ? nullptr : &entities_[it->second];
}

std::vector<const StepEntity*> StepIndex::OfType(std::string_view type) const {
    std::vector<const StepEntity*> out;
    for (const StepEntity& e : entities_) {
        if (e.type == type) out.push_back(&e);
    }
    return out;
}

std::vector<std::string_view> StepIndex::SplitArgs(std::string_view args) {
    std::vector<std::string_view> out;
    int depth = 0;
    size_t start = 0;
    for (size_t i = 0; i < args.size(); ++i) {
        const char c = args[i];
        if (c == '\'') {
            for (++i; i < args.size(); ++i) {
                if (args[i] != '\'') continue;
                if (i + 1 < args.size() && args[i + 1] == '\'') {
                    ++i;
                    continue;
                }
                break;
            }
        } else if (c == '(') {
            ++depth;
        } else if (c == ')') {
            --depth;
        } else if (c == ',' && depth == 0) {
            out.push_back(Trim(args.substr(start, i - start)));
            start = i + 1;
        }
    }
    if (!Trim(args).empty()) out.push_back(Trim(args.substr(start)));
    return out;
}

}  // namespace bimslam::change_detection
