// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// See ifc_face_bounds.hpp. Verified on IFC++ 0~git20190402 (Debian 12): the sample house of
// xBIM's tests (Revit 2015, IFC4) lists the hole of 7 window and chair faces first, and IFC++
// dropped each ("carve::triangulate::incorporateHolesIntoPolygon failed").
#include "host_tools/bim/ifc_face_bounds.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <optional>
#include <vector>

// IFC++ headers (system headers for the compiler: they are not -Wall clean).
#include <ifcpp/IFC4/include/IfcCartesianPoint.h>
#include <ifcpp/IFC4/include/IfcFace.h>
#include <ifcpp/IFC4/include/IfcFaceBound.h>
#include <ifcpp/IFC4/include/IfcFaceOuterBound.h>
#include <ifcpp/IFC4/include/IfcLengthMeasure.h>
#include <ifcpp/IFC4/include/IfcPolyLoop.h>
#include <ifcpp/model/BuildingModel.h>

namespace bimslam::bim::ifc {
namespace {

// A point's coordinates in the file's unit (2D points lie in z = 0); none when it is incomplete,
// as in a damaged file.
std::optional<Eigen::Vector3d> Coordinates(const IfcCartesianPoint* p) {
    if (p == nullptr || p->m_Coordinates.size() < 2 || p->m_Coordinates.size() > 3) return {};
    Eigen::Vector3d v = Eigen::Vector3d::Zero();
    for (size_t k = 0; k < p->m_Coordinates.size(); ++k) {
        if (!p->m_Coordinates[k]) return {};
        v[Eigen::Index(k)] = p->m_Coordinates[k]->m_value;
    }
    return v;
}

// The corners of an IfcPolyLoop in order. Other loops give none: IFC++ 0~git20190402 turns
// neither IfcEdgeLoop (CurveConverter::convertIfcLoop leaves it a TODO) nor IfcVertexLoop into
// points, so where they stand in a face makes no difference to it.
std::vector<Eigen::Vector3d> Corners(const IfcLoop* loop) {
    std::vector<Eigen::Vector3d> out;
    if (const auto* poly = dynamic_cast<const IfcPolyLoop*>(loop)) {
        for (const auto& p : poly->m_Polygon) {
            if (const auto v = Coordinates(p.get())) out.push_back(*v);
        }
    }
    return out;
}

// A planar loop's area: half the length of the sum of p_i x p_(i+1) over its edges (Newell's
// normal; the polygon's vector area). -1 for a missing bound, so that any loop beats it.
double Area(const IfcFaceBound* bound) {
    if (bound == nullptr || !bound->m_Bound) return -1.0;
    const std::vector<Eigen::Vector3d> p = Corners(bound->m_Bound.get());
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < p.size(); ++i) sum += p[i].cross(p[(i + 1) % p.size()]);
    return 0.5 * sum.norm();
}

}  // namespace

size_t PutOuterBoundsFirst(BuildingModel& model) {
    size_t reordered = 0;
    for (const auto& [id, entity] : model.getMapIfcEntities()) {
        auto* face = dynamic_cast<IfcFace*>(entity.get());
        if (face == nullptr || face->m_Bounds.size() < 2) continue;
        auto& bounds = face->m_Bounds;
        size_t marked = 0, outer = 0;
        for (size_t i = 0; i < bounds.size(); ++i) {
            if (dynamic_cast<const IfcFaceOuterBound*>(bounds[i].get()) != nullptr) {
                ++marked;
                outer = i;
            }
        }
        if (marked != 1) {  // IfcFace's rule HasOuterBound allows at most one; none is valid
            double largest = -1.0;
            for (size_t i = 0; i < bounds.size(); ++i) {
                const double area = Area(bounds[i].get());
                if (area > largest) {
                    largest = area;
                    outer = i;
                }
            }
        }
        if (outer == 0) continue;
        std::rotate(bounds.begin(), bounds.begin() + std::ptrdiff_t(outer),
                    bounds.begin() + std::ptrdiff_t(outer) + 1);
        ++reordered;
    }
    return reordered;
}

}  // namespace bimslam::bim::ifc
