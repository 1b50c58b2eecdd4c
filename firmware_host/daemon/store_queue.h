// The queue's order in SQL: priority first, then rank (the id unless an admin moved the job), then id.
#pragma once

// A job's rank: where an admin's `before` put it, else its id (first come, first served).
#define POPCUT_JOB_RANK "COALESCE(queue_rank, id)"
#define POPCUT_QUEUE_ORDER "priority DESC, " POPCUT_JOB_RANK ", id"
// The row is ahead of the job with id ID, priority PRIO and rank RANK (SQL expressions).
#define POPCUT_QUEUE_AHEAD(ID, PRIO, RANK)                                                                           \
  "(priority > " PRIO " OR (priority = " PRIO " AND (" POPCUT_JOB_RANK " < " RANK " OR (" POPCUT_JOB_RANK " = " RANK \
  " AND id < " ID "))))"
