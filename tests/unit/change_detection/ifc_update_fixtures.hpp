// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Fixtures of the updated-IFC tests (unit: IFC++; integration: web-ifc).
#pragma once

#include <Eigen/Core>

#include "algorithms/changes/voxel_mesh.hpp"
#include "host_tools/bim/bim_model.hpp"
#include "host_tools/bim/ifc_writer.hpp"
#include "host_tools/changes/change_report.hpp"

namespace bimslam::change_detection::test {

// A hand-written IFC2X3 file (the project's sample building is IFC4 only): project, site,
// building, one storey "Ground", one wall (4 x 0.2 x 3 m, entity #29), an owner history (#5), a
// project name with a ';' in it and a comment with one.
// A hand-written IFC2X3 file: project, site, building, one storey, one wall (4 x 0.2 x 3 m).
inline const char* const kTinyIfc2x3 = R"(ISO-10303-21;
HEADER;
FILE_DESCRIPTION(('ViewDefinition [CoordinationView]'),'2;1');
FILE_NAME('tiny.ifc','2024-01-01T00:00:00',('bimslam'),('bimslam'),'','bimslam test','');
FILE_SCHEMA(('IFC2X3'));
ENDSEC;
DATA;
#1=IFCPERSON($,$,'tester',$,$,$,$,$);
#2=IFCORGANIZATION($,'bimslam',$,$,$);
#3=IFCPERSONANDORGANIZATION(#1,#2,$);
#4=IFCAPPLICATION(#2,'1','bimslam test','test');
#5=IFCOWNERHISTORY(#3,#4,$,.ADDED.,$,$,$,0);
#6=IFCSIUNIT(*,.LENGTHUNIT.,$,.METRE.);
#7=IFCUNITASSIGNMENT((#6));
#8=IFCCARTESIANPOINT((0.,0.,0.));
#9=IFCAXIS2PLACEMENT3D(#8,$,$);
#10=IFCGEOMETRICREPRESENTATIONCONTEXT($,'Model',3,1.E-05,#9,$);
#11=IFCPROJECT('0YvctVUKr0kugbFTf53O9L',#5,'tiny; a name with a ; in it',$,$,$,$,(#10),#7);
#12=IFCLOCALPLACEMENT($,#9);
#13=IFCSITE('1YvctVUKr0kugbFTf53O9L',#5,'site',$,$,#12,$,$,.ELEMENT.,$,$,$,$,$);
#14=IFCLOCALPLACEMENT(#12,#9);
#15=IFCBUILDING('2YvctVUKr0kugbFTf53O9L',#5,'building',$,$,#14,$,$,.ELEMENT.,$,$,$);
#16=IFCLOCALPLACEMENT(#14,#9);
#17=IFCBUILDINGSTOREY('3YvctVUKr0kugbFTf53O9L',#5,'Ground',$,$,#16,$,$,.ELEMENT.,0.);
#18=IFCRELAGGREGATES('0AvctVUKr0kugbFTf53O9L',#5,$,$,#11,(#13));
#19=IFCRELAGGREGATES('0BvctVUKr0kugbFTf53O9L',#5,$,$,#13,(#15));
#20=IFCRELAGGREGATES('0CvctVUKr0kugbFTf53O9L',#5,$,$,#15,(#17));
#21=IFCCARTESIANPOINT((2.,0.));
#22=IFCAXIS2PLACEMENT2D(#21,$);
#23=IFCRECTANGLEPROFILEDEF(.AREA.,$,#22,4.,0.2);
#24=IFCDIRECTION((0.,0.,1.));
#25=IFCEXTRUDEDAREASOLID(#23,#9,#24,3.);
#26=IFCSHAPEREPRESENTATION(#10,'Body','SweptSolid',(#25));
#27=IFCPRODUCTDEFINITIONSHAPE($,$,(#26));
#28=IFCLOCALPLACEMENT(#16,#9);
/* a comment; with a semicolon */
#29=IFCWALLSTANDARDCASE('0EvctVUKr0kugbFTf53O9L',#5,'wall',$,$,#28,#27,$);
#30=IFCRELCONTAINEDINSPATIALSTRUCTURE('0DvctVUKr0kugbFTf53O9L',#5,$,$,(#29),#17);
ENDSEC;
END-ISO-10303-21;
)";

// A found object (a voxel block at `lo`) and a deviating or missing element.
inline SessionChanges Found(const bim::BimModel& model, const Eigen::Vector3f& lo, size_t element,
                            changes::Verdict verdict) {
    SessionChanges found;
    found.label = "test session";
    changes::NewObject obj;
    std::vector<Eigen::Vector3f> points;
    for (float x = 0.02f; x < 0.6f; x += 0.05f) {
        for (float y = 0.02f; y < 0.4f; y += 0.05f)
            points.push_back(lo + Eigen::Vector3f(x, y, 0.5f));
    }
    obj.solid = changes::MakeVoxelSolid(points, 0.1f, lo.z());
    obj.mesh = changes::VoxelSurface(obj.solid);
    obj.box_min = obj.solid.box_min();
    obj.box_max = obj.solid.box_max();
    obj.centroid = obj.solid.centroid();
    obj.volume_m3 = obj.solid.volume_m3();
    obj.points.assign(points.size(), 0);
    found.result.objects.push_back(obj);
    found.places.push_back({0, -1});
    found.object_global_ids.push_back(bim::IfcWriter::GlobalId(7, "object 0"));
    found.result.elements.resize(model.elements.size());
    found.result.elements[element].verdict = verdict;
    found.result.elements[element].offset = Eigen::Vector3d(0, 0.03, 0);
    return found;
}

}  // namespace bimslam::change_detection::test
