// isoterra — the libnoise peer: libnoise 1.0's Perlin module (Debian's
// libnoise-dev) as the fBm of the density d = -slope * y + amp * fBm, on
// the CPU with a few threads.  Built only when libnoise is found
// (bench/meson.build); the C side sees peer.h.
#include "peer.h"

#include <libnoise/noise.h>

#include <cmath>
#include <thread>
#include <vector>

namespace {

// (a module must not be copied: its destructor frees its source array)
void configure(noise::module::Perlin &m, const peer_fbm &f)
{
	m.SetOctaveCount(f.octaves);
	m.SetFrequency(f.freq);
	m.SetLacunarity(f.lacunarity);
	m.SetPersistence(f.persistence);
	m.SetSeed(f.seed);
	m.SetNoiseQuality(noise::QUALITY_BEST); // quintic s-curve, as isoterra's improved Perlin
}

// z slices z0, z0 + step, ... of the volume
void fill_slices(const peer_fbm *f, const noise::module::Perlin *m, float *out, int z0, int step)
{
	const long nx = f->dims[0], ny = f->dims[1];
	for (int k = z0; k < f->dims[2]; k += step) {
		double z = f->origin[2] + k * f->cell;
		for (int j = 0; j < ny; j++) {
			double y = f->origin[1] + j * f->cell;
			float *row = out + (k * ny + j) * nx;
			for (int i = 0; i < nx; i++) {
				double x = f->origin[0] + i * f->cell;
				row[i] = (float)(-f->slope * y + f->amp * m->GetValue(x, y, z));
			}
		}
	}
}

} // namespace

extern "C" const char *peer_libnoise_missing(void)
{
	return nullptr;
}

extern "C" int peer_libnoise_volume(const struct peer_fbm *f, float *out)
{
	if (f->octaves < 1 || f->octaves > noise::module::PERLIN_MAX_OCTAVE || f->threads < 1)
		return -1;
	noise::module::Perlin m;
	configure(m, *f);
	std::vector<std::thread> pool;
	for (int t = 1; t < f->threads; t++)
		pool.emplace_back(fill_slices, f, &m, out, t, f->threads);
	fill_slices(f, &m, out, 0, f->threads);
	for (auto &th : pool)
		th.join();
	return 0;
}

extern "C" double peer_libnoise_basis_std(int seed, int n)
{
	peer_fbm f = {};
	f.octaves = 1;
	f.seed = seed;
	f.freq = f.lacunarity = 1.0;
	f.persistence = 0.5;
	noise::module::Perlin m;
	configure(m, f);
	unsigned s = 12345u;
	double sum = 0, sum2 = 0;
	for (int i = 0; i < n; i++) {
		double p[3];
		for (double &c : p) {
			s = s * 1664525u + 1013904223u;
			c = (s >> 8) * (256.0 / 16777216.0);
		}
		double v = m.GetValue(p[0], p[1], p[2]);
		sum += v;
		sum2 += v * v;
	}
	double mean = sum / n;
	return std::sqrt(sum2 / n - mean * mean);
}
