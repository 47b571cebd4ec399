/* isoterra — the libnoise peer when libnoise is not installed (Debian:
 * libnoise-dev; tools/deps.sh installs it as an optional bench package). */
#include "peer.h"

const char *peer_libnoise_missing(void)
{
	return "libnoise not installed: peer skipped (Debian: libnoise-dev, then rebuild)";
}

int peer_libnoise_volume(const struct peer_fbm *f, float *out)
{
	(void)f;
	(void)out;
	return -1;
}

double peer_libnoise_basis_std(int seed, int n)
{
	(void)seed;
	(void)n;
	return 0;
}
