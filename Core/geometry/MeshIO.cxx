#include "geometry/MeshIO.h"

#include <cmath>
#include <fstream>
#include <sstream>

namespace hair
{

Status readVtkPolyData(const std::string& path, TriangleMesh& mesh)
{
  std::ifstream in(path);
  if (!in)
  {
    return Status::Error("cannot open the mesh file '" + path + "': check the path.");
  }
  std::string line;
  int lineNo = 0;
  auto error = [&](const std::string& what)
  {
    return Status::Error("the mesh file '" + path + "', line " + std::to_string(lineNo) + ": " +
                         what);
  };
  // Header: version line, title, ASCII, DATASET POLYDATA.
  std::vector<std::string> header;
  while (header.size() < 4 && std::getline(in, line))
  {
    ++lineNo;
    header.push_back(line);
  }
  if (header.size() < 4 || header[0].rfind("# vtk DataFile", 0) != 0)
  {
    return error("not a legacy VTK file (it must start with '# vtk DataFile').");
  }
  if (header[2].rfind("ASCII", 0) != 0)
  {
    return error("only ASCII legacy VTK files are read here; save the mesh as ASCII.");
  }
  if (header[3].find("POLYDATA") == std::string::npos)
  {
    return error("the dataset is not POLYDATA.");
  }
  TriangleMesh m;
  std::string keyword;
  while (in >> keyword)
  {
    if (keyword == "POINTS")
    {
      long n = 0;
      std::string type;
      if (!(in >> n >> type) || n < 0)
      {
        return error("a bad POINTS header.");
      }
      m.points.resize(n);
      for (long i = 0; i < n; ++i)
      {
        if (!(in >> m.points[i].x() >> m.points[i].y() >> m.points[i].z()))
        {
          return error("the file ends inside POINTS (point " + std::to_string(i) + " of " +
                       std::to_string(n) + "): it is truncated.");
        }
      }
    }
    else if (keyword == "POLYGONS")
    {
      long n = 0, size = 0;
      if (!(in >> n >> size) || n < 0)
      {
        return error("a bad POLYGONS header.");
      }
      for (long c = 0; c < n; ++c)
      {
        int k = 0;
        if (!(in >> k) || k < 0)
        {
          return error("the file ends inside POLYGONS: it is truncated.");
        }
        std::vector<int> ids(k);
        for (int& id : ids)
        {
          if (!(in >> id))
          {
            return error("the file ends inside POLYGONS: it is truncated.");
          }
        }
        for (int t = 1; t + 1 < k; ++t)
        {
          m.triangles.push_back({ids[0], ids[t], ids[t + 1]});
        }
      }
    }
    else
    {
      break; // point or cell data follow: not needed here
    }
  }
  if (Status s = m.validate("the mesh file '" + path + "'"); !s)
  {
    return s;
  }
  mesh = std::move(m);
  return Status::Ok();
}

} // namespace hair
