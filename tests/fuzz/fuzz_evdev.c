/* isoterra — libFuzzer harness: the evdev keyboard's event decoding
 * (hal/keys.c, hal_keys_feed_evdev): whatever a read returns.  A buffer
 * that is not a whole number of events decodes nothing; one that is
 * decodes each event, and a key changes each count by at most one. */
#include "hal.h"

#include <linux/input.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct hal_input in, zero;
	memset(&in, 0, sizeof(in));
	memset(&zero, 0, sizeof(zero));
	int n = hal_keys_feed_evdev(data, size, &in);
	if (size % sizeof(struct input_event)) {
		if (n != -1 || memcmp(&in, &zero, sizeof(in)))
			abort();
		return 0;
	}
	if (n < 0 || (size_t)n != size / sizeof(struct input_event))
		abort();
	int total = abs(in.select) + abs(in.change);
	for (int i = 0; i < HAL_ACTION_COUNT; i++)
		total += in.actions[i];
	for (int i = 0; i < HAL_FLY_AXES; i++)
		total += abs(in.fly[i]);
	if (total > n)
		abort();
	return 0;
}
