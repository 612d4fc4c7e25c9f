// Reader of the project's ".edges" arc lists, shared by the peer programs.
// One arc a line, "src dst holding tokens", '#' starts a comment, "# nodes N"
// gives the node count. The peers take integer holding times only (the
// benchmark families are integral); anything else is refused with exit 2.
#pragma once
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

struct ArcList {
    long long n = 0;
    std::vector<int> src, dst;
    std::vector<long long> weight, tokens;
};

inline ArcList read_edges(const char* path) {
    FILE* f = std::fopen(path, "r");
    if (!f) { std::fprintf(stderr, "%s: cannot open\n", path); std::exit(2); }
    ArcList g;
    long long top = -1, declared = -1;
    char line[4096];
    while (std::fgets(line, sizeof line, f)) {
        char* hash = std::strchr(line, '#');
        if (hash) {
            long long k;
            if (std::sscanf(hash, "# nodes %lld", &k) == 1) declared = k;
            *hash = '\0';
        }
        long long s, d, w, t;
        int got = std::sscanf(line, "%lld %lld %lld %lld", &s, &d, &w, &t);
        if (got <= 0) continue;
        if (got != 4) { std::fprintf(stderr, "%s: expected 'src dst holding tokens': %s\n", path, line); std::exit(2); }
        g.src.push_back((int)s); g.dst.push_back((int)d);
        g.weight.push_back(w); g.tokens.push_back(t);
        if (s > top) top = s;
        if (d > top) top = d;
    }
    std::fclose(f);
    g.n = declared >= 0 ? declared : top + 1;
    return g;
}

inline long long gcd_ll(long long a, long long b) {
    if (a < 0) a = -a;
    while (b) { long long r = a % b; a = b; b = r; }
    return a;
}
