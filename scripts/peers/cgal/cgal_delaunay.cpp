// Peer benchmark for scripts/bench-delaunay.sh: CGAL's sequential Delaunay_triangulation_3
// (Exact_predicates_inexact_constructions_kernel) on a point file in qhull's text format
// (first line the dimension 3, second the count, then `x y z` per point). The range insert
// spatially sorts the points (CGAL's BRIO + Hilbert sort), as our triangulator does.
// Prints one JSON object like bsp2vdg's tetrahedralize example:
//   {"points": N, "vertices": V, "tetrahedra": T, "seconds": S}
// where seconds times the triangulation only (file reading excluded).
//
// Build: g++ -O3 -DNDEBUG -o cgal_delaunay cgal_delaunay.cpp -lgmp -lmpfr
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <vector>

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Delaunay_triangulation_3<K> Delaunay;
typedef K::Point_3 Point;

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: cgal_delaunay POINTS.txt\n");
        return 2;
    }
    std::ifstream in(argv[1]);
    if (!in) {
        std::fprintf(stderr, "cannot read %s\n", argv[1]);
        return 1;
    }
    long dim = 0, count = 0;
    if (!(in >> dim >> count) || dim != 3 || count < 0) {
        std::fprintf(stderr, "%s: bad header (expected dimension 3 and a count)\n", argv[1]);
        return 1;
    }
    std::vector<Point> points;
    points.reserve(static_cast<size_t>(count));
    for (long i = 0; i < count; ++i) {
        double x, y, z;
        if (!(in >> x >> y >> z)) {
            std::fprintf(stderr, "%s: point %ld: missing or bad coordinate\n", argv[1], i);
            return 1;
        }
        points.emplace_back(x, y, z);
    }
    auto start = std::chrono::steady_clock::now();
    Delaunay T;
    T.insert(points.begin(), points.end());
    double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("{\"points\": %ld, \"vertices\": %zu, \"tetrahedra\": %zu, \"seconds\": %.6f}\n",
                count, static_cast<size_t>(T.number_of_vertices()),
                static_cast<size_t>(T.number_of_finite_cells()), seconds);
    return 0;
}
