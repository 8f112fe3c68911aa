/* libFuzzer target: arbitrary bytes as a node config file, then the cross-setting checks; a
 * config either loads into checked values or is refused with a message naming a line. */
#include <stdio.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "node/config.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0)
        return 0; /* fmemopen refuses an empty buffer */
    FILE *f = fmemopen((void *)data, size, "r");
    if (f == NULL)
        return 0;
    struct mn_config cfg;
    char err[MN_CONFIG_ERR];
    err[0] = '\0';
    mn_config_defaults(&cfg);
    if (mn_config_load_stream(&cfg, f, "fuzz.conf", err, sizeof(err)) == 0) {
        mn_config_check(&cfg, err, sizeof(err));
    } else if (strncmp(err, "fuzz.conf", 9) != 0) {
        abort(); /* every refusal names the file */
    }
    fclose(f);
    return 0;
}
