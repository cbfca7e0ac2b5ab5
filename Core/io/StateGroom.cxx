#include "io/StateGroom.h"

#include "io/Hdf5.h"
#include "io/StateFormat.h"

namespace hair::detail
{

using namespace hdf5;
namespace sf = stateformat;

Status writeGroom(hid_t file, const StateHeader& header)
{
  const StateGroom& g = header.groom;
  if (g.empty())
  {
    return Status::Ok();
  }
  Handle group(H5Gcreate2(file, sf::Groom, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  bool ok = group.valid();
  const hsize_t strands = header.numberOfStrands();
  if (ok && !g.curveOffsets.empty())
  {
    ok = writeArray(file, sf::CurveOffsets, H5T_NATIVE_INT64, g.curveOffsets.size(),
                    g.curveOffsets.data()) &&
         writeRows(file, sf::CurvePoints, g.curvePoints.size(), 3,
                   g.curvePoints.empty() ? nullptr : g.curvePoints[0].data());
  }
  if (ok && !g.restCoordinates.empty())
  {
    ok = writeRows(file, sf::RestCoordinates, strands, hsize_t(header.coordinatesPerStrand),
                   g.restCoordinates.data());
  }
  for (const auto& [name, values] : g.strandValues)
  {
    ok = ok &&
         writeArray(group.get(), name.c_str(), H5T_NATIVE_DOUBLE, values.size(), values.data());
  }
  return ok ? Status::Ok() : Status::Error(std::string("cannot write ") + sf::Groom + ".");
}

void readGroom(hid_t file, StateHeader& header, double maxValues)
{
  header.groom = StateGroom();
  htri_t has;
  H5E_BEGIN_TRY
  {
    has = H5Lexists(file, sf::Groom, H5P_DEFAULT);
  }
  H5E_END_TRY;
  if (has <= 0)
  {
    return;
  }
  StateGroom g;
  const hsize_t strands = header.numberOfStrands();
  H5E_BEGIN_TRY
  {
    Handle group(H5Gopen2(file, sf::Groom, H5P_DEFAULT));
    std::vector<std::string> names;
    if (group.valid() && linkNames(group.get(), names))
    {
      for (const std::string& name : names)
      {
        Handle d(H5Dopen2(group.get(), name.c_str(), H5P_DEFAULT));
        const auto dims = extent(d.get());
        const std::string path = std::string(sf::Groom) + "/" + name;
        double values = dims.empty() ? 0.0 : 1.0;
        for (const hsize_t n : dims)
        {
          values *= double(n);
        }
        if (values > maxValues)
        {
          continue;
        }
        if (path == sf::CurveOffsets && dims.size() == 1 && dims[0] == strands + 1)
        {
          g.curveOffsets.resize(dims[0]);
          if (!readWhole(d.get(), H5T_NATIVE_INT64, g.curveOffsets.data()))
          {
            g.curveOffsets.clear();
          }
        }
        else if (path == sf::CurvePoints && dims.size() == 2 && dims[1] == 3)
        {
          g.curvePoints.resize(dims[0]);
          if (dims[0] > 0 && !readWhole(d.get(), H5T_NATIVE_DOUBLE, g.curvePoints[0].data()))
          {
            g.curvePoints.clear();
          }
        }
        else if (path == sf::RestCoordinates && dims.size() == 2 && dims[0] == strands &&
                 dims[1] == hsize_t(header.coordinatesPerStrand))
        {
          g.restCoordinates.resize(dims[0] * dims[1]);
          if (!readWhole(d.get(), H5T_NATIVE_DOUBLE, g.restCoordinates.data()))
          {
            g.restCoordinates.clear();
          }
        }
        else if (dims.size() == 1 && dims[0] == strands)
        {
          std::vector<double> v(dims[0]);
          if (readWhole(d.get(), H5T_NATIVE_DOUBLE, v.data()))
          {
            g.strandValues[name] = std::move(v);
          }
        }
      }
    }
  }
  H5E_END_TRY;
  // The curves only as a whole: offsets and points that agree.
  if (g.curveOffsets.empty() || g.curveOffsets.back() != std::int64_t(g.curvePoints.size()))
  {
    g.curveOffsets.clear();
    g.curvePoints.clear();
  }
  StateHeader check = header;
  check.groom = g;
  if (check.validate())
  {
    header.groom = std::move(g);
  }
}

} // namespace hair::detail
