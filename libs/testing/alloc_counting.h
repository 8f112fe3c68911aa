/* For C tests that check a loop allocates nothing (a frame read, a detector run): every malloc,
 * calloc and realloc of the test program, the library's under test included, goes through a
 * counting wrapper. A test program gets them from mocap_count_allocations(TARGET) in
 * cmake/Testing.cmake, which links alloc_counting.c with -Wl,--wrap for the three. */
#ifndef MN_ALLOC_COUNTING_H
#define MN_ALLOC_COUNTING_H

/* Allocations made so far by the program. */
unsigned long mn_alloc_count(void);

#endif
