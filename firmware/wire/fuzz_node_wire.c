/* libFuzzer target: the firmware's datagram decoder on arbitrary bytes; whatever it accepts
 * must re-encode within the datagram limit. */
#include <stdint.h>
#include <stdlib.h>

#include "wire/wire.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	static mocap_v1_Packet packet;
	uint8_t out[MN_WIRE_MAX_DATAGRAM];
	size_t out_size;
	const char *reason;

	if (mn_wire_decode(data, size, &packet, &reason) == 0 &&
	    mn_wire_encode(&packet, out, sizeof out, &out_size, &reason) != 0)
		abort();
	return 0;
}
