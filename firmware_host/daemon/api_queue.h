// What the queue's requests ask: Idempotency-Key, the list's filters, an admin's move (docs/api.md).
#pragma once

#include <string>

#include "api_handlers.h"
#include "store.h"

namespace popcut::daemon {

// The Idempotency-Key header: at most one, 1 to 255 visible ASCII characters ("" when absent).
std::string idempotency_key(const Req& req);
// SHA-256 (hex) of what a submission asks for, whatever its encoding: a retried multipart
// upload has a new boundary, and two requests with one key are the same when these are.
std::string request_digest(const NewJob& job);
// ?limit=, ?state=a,b, ?device=, ?since= (unix seconds); owner left empty.
JobFilter job_filter(const Req& req);
// A submission's `copies`: a whole number from 1 to 1000 (400 naming the field otherwise).
int copies_field(const json& v);
// POST /api/v1/jobs with a JSON body already read (the designer's "send to cutter" adds the model).
void submit_json_job(ApiContext& api, const Caller& caller, const Req& req, const json& body, Res& res);
// Checks a new job against its device, records it (Idempotency-Key honoured) and answers 201.
void queue_job(ApiContext& api, NewJob& nj, const std::string& source, Res& res);
// PATCH /api/v1/jobs/N: {"priority": P} and/or {"before": M}.
Reorder reorder_request(const Req& req);

}  // namespace popcut::daemon
