/* libFuzzer target: arbitrary datagrams into the node's control handler, on both sockets, with
 * one handler kept across inputs so mask-chunk assembly state is fuzzed too. */
#include <stddef.h>
#include <stdint.h>

#include "node/control.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static struct mn_control *ctl;
    if (ctl == NULL)
        ctl = mn_control_new(5);
    if (ctl == NULL)
        return 0;
    struct mn_command cmd;
    const char *why;
    for (int announce = 0; announce < 2; announce++) {
        enum mn_control_result r = mn_control_handle(ctl, data, size, announce, &cmd, &why);
        /* A mask image handed out must be readable in full. */
        if (r == MN_CONTROL_ACCEPTED && cmd.kind == MN_CMD_MASK_BITS) {
            size_t bytes = ((size_t)cmd.u.bits.cells_x * cmd.u.bits.cells_y + 7) / 8;
            volatile uint8_t sum = 0;
            for (size_t i = 0; i < bytes; i++)
                sum ^= cmd.u.bits.bits[i];
            (void)sum;
        }
    }
    return 0;
}
