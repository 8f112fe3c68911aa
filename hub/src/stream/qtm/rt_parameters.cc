// GetParameters XML (see rt_parameters.h).
#include "stream/qtm/rt_parameters.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <sstream>

#include "stream/qtm/rt_command.h"

namespace mocap::stream::qtm {
namespace {

std::string Number(double v) {
  char text[64];
  std::snprintf(text, sizeof text, "%.6g", v);
  return text;
}

// A stable colour per label or body: RGBColor is a decimal integer with red in bits 0-7 (what
// Qualisys' own C++ SDK parses).
uint32_t Colour(int index) {
  static const uint32_t kPalette[] = {0x0000ff, 0x00ff00, 0xff0000, 0x00ffff, 0xff00ff, 0xffff00, 0x0080ff, 0xff0080};
  return kPalette[index % 8];
}

// A {Current, Min, Max} block.
void Range(std::ostringstream& x, const char* name, int current, int min, int max) {
  x << "<" << name << "><Current>" << current << "</Current><Min>" << min << "</Min><Max>" << max << "</Max></"
    << name << ">\n";
}

// Processing_Actions and its two siblings: the hub tracks in 3D, nothing else of QTM's list.
void ProcessingActions(std::ostringstream& x, const char* name) {
  x << "<" << name << ">\n<PreProcessing2D>False</PreProcessing2D>\n<Tracking>3D</Tracking>\n";
  for (const char* action : {"TwinSystemMerge", "SplineFill", "AIM", "Track6DOF", "ForceData", "GazeVector",
                             "ExportTSV", "ExportC3D", "ExportMatlabFile", "ExportAviFile"})
    x << "<" << action << ">False</" << action << ">\n";
  x << "</" << name << ">\n";
}

void General(std::ostringstream& x, const RtSystem& s) {
  x << "<General>\n<Frequency>" << Number(s.rate_hz) << "</Frequency>\n"
    << "<Capture_Time>0</Capture_Time>\n<Start_On_External_Trigger>False</Start_On_External_Trigger>\n"
    << "<Start_On_Trigger_NO>False</Start_On_Trigger_NO>\n<Start_On_Trigger_NC>False</Start_On_Trigger_NC>\n"
    << "<Start_On_Trigger_Software>False</Start_On_Trigger_Software>\n"
    << "<External_Time_Base>\n<Enabled>False</Enabled>\n<Signal_Source>Control port</Signal_Source>\n"
    << "<Signal_Mode>Periodic</Signal_Mode>\n<Frequency_Multiplier>1</Frequency_Multiplier>\n"
    << "<Frequency_Divisor>1</Frequency_Divisor>\n<Frequency_Tolerance>0</Frequency_Tolerance>\n"
    << "<Nominal_Frequency>None</Nominal_Frequency>\n<Signal_Edge>Positive</Signal_Edge>\n"
    << "<Signal_Shutter_Delay>0</Signal_Shutter_Delay>\n<Non_Periodic_Timeout>0</Non_Periodic_Timeout>\n"
    << "</External_Time_Base>\n";
  ProcessingActions(x, "Processing_Actions");
  ProcessingActions(x, "RealTime_Processing_Actions");
  ProcessingActions(x, "Reprocessing_Actions");
  x << "<Camera_System><Type>Unknown</Type></Camera_System>\n";
  for (const Camera& c : s.rig.cameras) {
    const Eigen::Vector3d centre = c.CenterInWorld();
    const Eigen::Matrix3d world_from_cam = c.rotation.transpose();
    x << "<Camera>\n<ID>" << c.id << "</ID>\n<Model>mocap-node</Model>\n<Underwater>False</Underwater>\n"
      << "<Supports_HW_Sync>True</Supports_HW_Sync>\n<Serial>" << c.id << "</Serial>\n<Mode>Marker</Mode>\n"
      << "<Video_Frequency>0</Video_Frequency>\n";
    // Exposure and threshold live on the nodes (mocap-hub nodes); 0 here means "not told".
    Range(x, "Video_Exposure", 0, 0, 0);
    Range(x, "Video_Flash_Time", 0, 0, 0);
    Range(x, "Marker_Exposure", 0, 0, 0);
    Range(x, "Marker_Threshold", 0, 0, 0);
    x << "<Position>\n<X>" << Number(centre.x()) << "</X>\n<Y>" << Number(centre.y()) << "</Y>\n<Z>"
      << Number(centre.z()) << "</Z>\n";
    for (int col = 0; col < 3; ++col)
      for (int row = 0; row < 3; ++row)
        x << "<Rot_" << row + 1 << "_" << col + 1 << ">" << Number(world_from_cam(row, col)) << "</Rot_" << row + 1
          << "_" << col + 1 << ">\n";
    x << "</Position>\n<Orientation>0</Orientation>\n<Marker_Res>\n<Width>" << c.intrinsics.width * 64
      << "</Width>\n<Height>" << c.intrinsics.height * 64 << "</Height>\n</Marker_Res>\n<Video_Res>\n<Width>0</Width>\n<Height>0</Height>\n</Video_Res>\n<Marker_FOV>\n"
      << "<Left>0</Left>\n<Top>0</Top>\n<Right>" << std::max(0, c.intrinsics.width - 1) << "</Right>\n<Bottom>"
      << std::max(0, c.intrinsics.height - 1) << "</Bottom>\n</Marker_FOV>\n</Camera>\n";
  }
  x << "</General>\n";
}

void ThreeD(std::ostringstream& x, const RtSystem& s, const RtNames& names) {
  x << "<The_3D>\n<AxisUpwards>" << s.axis_upwards << "</AxisUpwards>\n<CalibrationTime></CalibrationTime>\n"
    << "<Labels>" << names.label_count() << "</Labels>\n";
  for (size_t i = 0; i < names.label_count(); ++i)
    x << "<Label>\n<Name>" << XmlEscape(names.label_name(i)) << "</Name>\n<RGBColor>" << Colour(static_cast<int>(i))
      << "</RGBColor>\n</Label>\n";
  x << "<Bones></Bones>\n</The_3D>\n";
}

// A body in both layouts readers know: RGBColor (up to protocol 1.20) and, from 1.21 on, the
// elements Qualisys' C++ SDK requires (colour attributes, limits, filter, points, and the data
// origin and orientation: global, identity). The points are the definition's markers in the
// body frame (none for a body serve has no definition of); the limits are neutral.
void Body(std::ostringstream& x, const std::string& name, uint32_t colour, const RigidBodyDefinition* definition) {
  x << "<Body>\n<Name>" << XmlEscape(name) << "</Name>\n<Enabled>true</Enabled>\n<RGBColor>" << colour
    << "</RGBColor>\n<Color R=\"" << (colour & 0xff) << "\" G=\"" << (colour >> 8 & 0xff) << "\" B=\""
    << (colour >> 16 & 0xff) << "\"/>\n<MaximumResidual>0</MaximumResidual>\n"
    << "<MinimumMarkersInBody>3</MinimumMarkersInBody>\n<BoneLengthTolerance>0</BoneLengthTolerance>\n"
    << "<Filter Preset=\"No filter\"/>\n<Points>";
  if (definition) {
    x << "\n";
    for (size_t m = 0; m < definition->markers.size(); ++m) {
      const Eigen::Vector3d& p = definition->markers[m];
      x << "<Point X=\"" << p.x() << "\" Y=\"" << p.y() << "\" Z=\"" << p.z() << "\" Virtual=\"0\" PhysicalId=\"0\" Name=\""
        << XmlEscape(definition->name) << "_" << (m + 1) << "\"/>\n";
    }
  }
  x << "</Points>\n"
    << "<Data_origin X=\"0\" Y=\"0\" Z=\"0\" Relative_body=\"0\">0</Data_origin>\n"
    << "<Data_orientation R11=\"1\" R12=\"0\" R13=\"0\" R21=\"0\" R22=\"1\" R23=\"0\" R31=\"0\" R32=\"0\" "
       "R33=\"1\" Relative_body=\"0\">0</Data_orientation>\n</Body>\n";
}

void SixD(std::ostringstream& x, const RtSystem& system, const RtNames& names) {
  x << "<The_6D>\n<Bodies>" << names.bodies().size() << "</Bodies>\n";
  int i = 0;
  for (const auto& [id, name] : names.bodies()) {
    const RigidBodyDefinition* definition = nullptr;
    for (const RigidBodyDefinition& d : system.bodies)
      if (d.name == name) definition = &d;
    Body(x, name, Colour(i++), definition);
  }
  x << "<Euler>\n<First>Roll</First>\n<Second>Pitch</Second>\n<Third>Yaw</Third>\n</Euler>\n</The_6D>\n";
}

}  // namespace

std::string AxisUpwards(const Rig& rig) {
  Eigen::Vector3d up = Eigen::Vector3d::Zero();
  // Image y points down (OpenCV): a camera's up in world is -(row 2 of cam_from_world).
  for (const Camera& c : rig.cameras) up -= c.rotation.row(1).transpose();
  if (up.norm() < 1e-9) return "+Z";
  int axis = 0;
  up.cwiseAbs().maxCoeff(&axis);
  return std::string(up[axis] < 0 ? "-" : "+") + "XYZ"[axis];
}

std::string XmlEscape(const std::string& text) {
  std::string out;
  for (char ch : text) {
    switch (ch) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default:
        // Control bytes have no place in XML 1.0 character data.
        if (static_cast<unsigned char>(ch) >= 0x20 || ch == '\t' || ch == '\n') out += ch;
    }
  }
  return out;
}

std::string ParametersXml(const RtSystem& system, const RtNames& names, uint32_t blocks, int version_minor) {
  std::ostringstream x;
  const std::string root = "QTM_Parameters_Ver_1." + std::to_string(version_minor);
  x << "<" << root << ">\n";
  if (blocks & kGeneral) General(x, system);
  if (blocks & k3dParameters) ThreeD(x, system, names);
  if (blocks & k6dParameters) SixD(x, system, names);
  x << "</" << root << ">\n";
  return x.str();
}

}  // namespace mocap::stream::qtm
