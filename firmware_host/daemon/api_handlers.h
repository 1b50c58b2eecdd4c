// The route handlers, by resource; the route table in http_api.cpp says which path and method
// each answers and which token it needs (checked before the handler runs).
#pragma once

#include <httplib.h>

#include "api_context.h"

namespace popcut::daemon {

using Req = httplib::Request;
using Res = httplib::Response;

// api_service.cpp: health, metrics and the kiosk page (no token).
void get_health(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void get_metrics(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void get_kiosk_page(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void get_kiosk_script(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void get_kiosk_style(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void get_operator_page(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void get_operator_script(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void get_operator_style(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void get_design_page(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void get_design_script(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void get_design_style(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void get_design_view_script(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void get_design_files_script(ApiContext& api, const Caller& caller, const Req& req, Res& res);
// three.js and its orbit controls from [server] three_dir (Debian's libjs-three).
void get_three_script(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void get_orbit_controls(ApiContext& api, const Caller& caller, const Req& req, Res& res);

// api_stats.cpp (admin)
void get_stats(ApiContext& api, const Caller& caller, const Req& req, Res& res);

// api_devices.cpp
void list_devices(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void list_materials(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void pause_device(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void resume_device(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void reset_blade(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void confirm_sheet(ApiContext& api, const Caller& caller, const Req& req, Res& res);

// api_jobs.cpp
void submit_job(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void list_jobs(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void get_job(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void patch_job(ApiContext& api, const Caller& caller, const Req& req, Res& res);  // admin: priority, before
void get_job_pattern(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void get_job_preview(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void cancel_job(ApiContext& api, const Caller& caller, const Req& req, Res& res);
// api_pause.cpp: POST /api/v1/jobs/N/pause and /continue (docs/api.md "Pausing a cut").
void pause_job(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void continue_job(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void resume_job(ApiContext& api, const Caller& caller, const Req& req, Res& res);

// api_models.cpp: example models, pictures of a model before it is queued, mesh import.
void list_examples(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void get_example(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void render_pattern(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void render_preview(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void import_model(ApiContext& api, const Caller& caller, const Req& req, Res& res);
// drawing_upload.cpp: a drawing (SVG, DXF, FOLD) read as a card or a folding sheet for the kiosk.
void import_drawing(ApiContext& api, const Caller& caller, const Req& req, Res& res);

// api_designs.cpp: the designer's drafts and live sessions (docs/api.md "Designs").
void create_design(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void list_designs(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void list_fonts(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void get_design(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void rename_design(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void delete_design(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void add_design_item(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void remove_design_item(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void undo_design(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void redo_design(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void get_design_file(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void get_design_pattern(ApiContext& api, const Caller& caller, const Req& req, Res& res);
void submit_design(ApiContext& api, const Caller& caller, const Req& req, Res& res);

}  // namespace popcut::daemon
