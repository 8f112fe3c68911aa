/* Firmware version string reported in NodeStatus and by --version; the build sets
 * MN_VERSION_STRING from the CMake project version. */
#ifndef MN_NODE_VERSION_H
#define MN_NODE_VERSION_H

#ifdef MN_VERSION_STRING
#define MN_VERSION MN_VERSION_STRING
#else
#define MN_VERSION "unknown"
#endif

#endif
