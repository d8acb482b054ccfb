/* memory_budget.h - admits jobs to run only while their estimated memory fits.
 *
 * Why: a job's memory grows with the pixels of its images (decoded as floats, re-baked,
 * rendered), and a 250 KB PNG may declare 256 megapixels; with several workers, a few such
 * uploads at once would take more memory than the machine has. Each job's need is
 * estimated from the pixels its images declare (read from the headers at upload); a worker
 * waits, its job still queued, until the need fits beside the running jobs'. A job larger
 * than the whole budget runs alone rather than never. Does not: measure real use, or stop a
 * job that outgrows its estimate. One mutex and condition variable. */
#ifndef TEXOPT_SERVER_MEMORY_BUDGET_H
#define TEXOPT_SERVER_MEMORY_BUDGET_H

#include <stdint.h>

typedef struct memory_budget memory_budget;

/* A budget of `bytes` (> 0). NULL when out of memory. */
memory_budget *memory_budget_create(uint64_t bytes);
void memory_budget_destroy(memory_budget *budget); /* accepts NULL; nobody may wait on it */

/* The estimated peak bytes of a job whose images hold `pixels` pixels in all. */
uint64_t memory_budget_job_bytes(uint64_t pixels);

/* Waits until `need` fits beside what running jobs hold (or nothing runs), then holds it.
 * Returns 0, or -1 once the budget is closed (nothing held). */
int memory_budget_acquire(memory_budget *budget, uint64_t need);
void memory_budget_release(memory_budget *budget, uint64_t need);

/* Bytes held now. */
uint64_t memory_budget_held(memory_budget *budget);

/* Wakes every waiter with -1 and refuses further acquires (shutdown). */
void memory_budget_close(memory_budget *budget);

#endif
