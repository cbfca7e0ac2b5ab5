// Collision look-up against CGAL's exact answer, side by side on the same random points:
// the bundled body (26 756 triangles) and a refined copy of it (each triangle split into
// 36, 963 216 triangles, the same surface). The table's cost must not change with the
// mesh; CGAL's grows with it. Scripts/bench_collision.py runs this and prints the ratios.
#include "collision/BodyPartList.h"
#include "collision/CollisionTable.h"
#include "collision/PosedPart.h"
#include "geometry/MeshIO.h"

#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <random>
#include <stdexcept>

using namespace hair;

namespace
{

/// Splits every triangle into n² by a regular grid on it (same surface, n² times the
/// triangles; shared edges get the same new points, so the result stays closed).
TriangleMesh refine(const TriangleMesh& in, int n)
{
  TriangleMesh out;
  out.points = in.points;
  std::map<std::pair<int, int>, std::vector<int>> edgePoints; // keyed (min, max)
  auto edge = [&](int a, int b)
  {
    const bool flip = a > b;
    const auto key = std::minmax(a, b);
    auto it = edgePoints.find(key);
    if (it == edgePoints.end())
    {
      std::vector<int> ids(n + 1);
      ids[0] = key.first;
      ids[n] = key.second;
      for (int k = 1; k < n; ++k)
      {
        out.points.push_back(in.points[key.first] +
                             (in.points[key.second] - in.points[key.first]) * k / n);
        ids[k] = static_cast<int>(out.points.size()) - 1;
      }
      it = edgePoints.emplace(key, ids).first;
    }
    std::vector<int> ids = it->second;
    if (flip)
    {
      std::reverse(ids.begin(), ids.end());
    }
    return ids;
  };
  for (const auto& t : in.triangles)
  {
    // grid[i][j]: point A + i/n (B − A) + j/n (C − A), i + j ≤ n
    std::vector<std::vector<int>> grid(n + 1, std::vector<int>(n + 1, -1));
    const auto ab = edge(t[0], t[1]), ac = edge(t[0], t[2]), bc = edge(t[1], t[2]);
    for (int k = 0; k <= n; ++k)
    {
      grid[k][0] = ab[k];
      grid[0][k] = ac[k];
      grid[n - k][k] = bc[k];
    }
    const Eigen::Vector3d A = in.points[t[0]], B = in.points[t[1]], C = in.points[t[2]];
    for (int i = 1; i < n; ++i)
    {
      for (int j = 1; i + j < n; ++j)
      {
        out.points.push_back(A + (B - A) * i / n + (C - A) * j / n);
        grid[i][j] = static_cast<int>(out.points.size()) - 1;
      }
    }
    for (int i = 0; i < n; ++i)
    {
      for (int j = 0; i + j < n; ++j)
      {
        out.triangles.push_back({grid[i][j], grid[i + 1][j], grid[i][j + 1]});
        if (i + j + 1 < n)
        {
          out.triangles.push_back({grid[i + 1][j], grid[i + 1][j + 1], grid[i][j + 1]});
        }
      }
    }
  }
  return out;
}

struct Scene
{
  TriangleMesh mesh;
  std::unique_ptr<MeshQueries> exact;
  CollisionTable head;
  std::vector<Eigen::Vector3d> points;
};

Scene& scene(int refinement)
{
  static std::map<int, std::unique_ptr<Scene>> scenes;
  auto& s = scenes[refinement];
  if (!s)
  {
    s = std::make_unique<Scene>();
    TriangleMesh body;
    std::vector<BodyPartSpec> parts;
    if (!readVtkPolyData(std::string(HAIR_DATA_DIR) + "/body.vtk", body).ok() ||
        !readBodyParts(std::string(HAIR_DATA_DIR) + "/body_parts.txt", parts).ok())
    {
      throw std::runtime_error("cannot read Data/body.vtk or Data/body_parts.txt");
    }
    s->mesh = refinement > 1 ? refine(body, refinement) : body;
    s->exact = std::make_unique<MeshQueries>(s->mesh);
    const Status built = s->head.build(parts.at(0).spec, *s->exact);
    if (!built)
    {
      throw std::runtime_error(built.message());
    }
    // Random points around the head and neck, as hair nodes would be.
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> X(-0.12, 0.12), Y(1.40, 1.70), Z(-0.09, 0.20);
    s->points.resize(4096);
    for (auto& p : s->points)
    {
      p = Eigen::Vector3d(X(rng), Y(rng), Z(rng));
    }
  }
  return *s;
}

void BM_TableLookup(benchmark::State& state)
{
  Scene& s = scene(static_cast<int>(state.range(0)));
  const PosedPart head = PosedPart::still(s.head); // a look-up at the part's pose
  std::size_t i = 0;
  int inside = 0;
  for (auto _ : state)
  {
    const TableQuery q = head.query(s.points[i++ & 4095]);
    inside += q.inside;
    benchmark::DoNotOptimize(q);
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["triangles"] = static_cast<double>(s.mesh.triangles.size());
  state.counters["inside_share"] = double(inside) / state.iterations();
}

void BM_CgalExact(benchmark::State& state)
{
  Scene& s = scene(static_cast<int>(state.range(0)));
  std::size_t i = 0;
  int inside = 0;
  for (auto _ : state)
  {
    const Eigen::Vector3d& p = s.points[i++ & 4095];
    const Eigen::Vector3d c = s.exact->closestPoint(p);
    const bool in = s.exact->isInside(p);
    inside += in;
    benchmark::DoNotOptimize(c);
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["triangles"] = static_cast<double>(s.mesh.triangles.size());
  state.counters["inside_share"] = double(inside) / state.iterations();
}

void BM_TableBuild40x40(benchmark::State& state)
{
  Scene& s = scene(static_cast<int>(state.range(0)));
  for (auto _ : state)
  {
    CollisionTable t;
    benchmark::DoNotOptimize(t.build(s.head.spec(), *s.exact));
  }
  state.counters["triangles"] = static_cast<double>(s.mesh.triangles.size());
}

} // namespace

// Argument: refinement (1: the bundled body; 6: each triangle split into 36).
BENCHMARK(BM_TableLookup)->Arg(1)->Arg(6);
BENCHMARK(BM_CgalExact)->Arg(1)->Arg(6);
BENCHMARK(BM_TableBuild40x40)->Arg(1)->Arg(6)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
