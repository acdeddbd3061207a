#pragma once
// The REST endpoints (docs/api.md). Each parses, calls the repositories, and returns JSON.
#include "server/api/api_context.h"

namespace incise::server::api {

ApiResponse health(ApiContext& ctx);
// Readiness (Kubernetes' readinessProbe): 200 once the database answers, else 503.
ApiResponse ready(ApiContext& ctx);

ApiResponse login(ApiContext& ctx);
ApiResponse logout(ApiContext& ctx);
ApiResponse me(ApiContext& ctx);
// POST /api/me/password {"current_password", "new_password"}: the caller's own change, also
// while an admin's reset requires one (clears it); audited without secrets.
ApiResponse change_own_password(ApiContext& ctx);

ApiResponse list_users(ApiContext& ctx);
ApiResponse create_user(ApiContext& ctx);
// admin: replaces the instructors of a trainee ({"instructor_ids": [...]}); audited.
ApiResponse set_trainee_instructors(ApiContext& ctx);
// PATCH /api/users/{id} {"disabled": bool}: an admin disables (ending their logins) or re-enables
// a user; never themself. Audited with before and after.
ApiResponse update_user(ApiContext& ctx);
// POST /api/users/{id}/password {"password"}: an admin sets a temporary password that the user
// must replace at their next login; ends their logins. Audited without the password.
ApiResponse reset_user_password(ApiContext& ctx);

ApiResponse list_stations(ApiContext& ctx);
ApiResponse create_station(ApiContext& ctx);
// PATCH /api/stations/{id}: an admin sets what the station can run ({"kind": "laparoscopy"})
// and retires it or returns it to service ({"retired": true}); audited with before and after.
ApiResponse update_station(ApiContext& ctx);
// GET /api/stations/{id}/tasks: the tasks the station can run, each with what locks it for the
// trainee asking (curriculum/station_offer.h).
ApiResponse station_tasks(ApiContext& ctx);
ApiResponse get_station_calibration(ApiContext& ctx);  // admin, instructor
ApiResponse put_station_calibration(ApiContext& ctx);  // admin; 422 with the first problem

ApiResponse list_bookings(ApiContext& ctx);
// Any role: a station's active bookings from a week ago on, for its calendar; a trainee sees
// others' as taken slots only (no id, no name).
ApiResponse station_schedule(ApiContext& ctx);
ApiResponse create_booking(ApiContext& ctx);
ApiResponse cancel_booking(ApiContext& ctx);

ApiResponse list_sessions(ApiContext& ctx);
ApiResponse list_recordings(ApiContext& ctx);
ApiResponse list_scores(ApiContext& ctx);
// admin: every score as CSV (RFC 4180), one row per metric of an attempt; audited.
ApiResponse export_scores_csv(ApiContext& ctx);
// Proficiency-based progression: the caller's own, or (instructors, admins, the trainee
// themself) a trainee's: per task attempts, the current run of passes, mastered, unlocked.
ApiResponse my_progress(ApiContext& ctx);
// Review of an attempt: annotations at a time of its recording and score adjustments (pass or
// fail with a reason, audited). Read: the session's trainee, instructors, admins; write:
// instructors, admins.
ApiResponse list_annotations(ApiContext& ctx);
ApiResponse add_annotation(ApiContext& ctx);
ApiResponse list_adjustments(ApiContext& ctx);
ApiResponse adjust_score(ApiContext& ctx);
// The review of an attempt (its trainee, instructors, admins): events and signal timelines from
// the recording, results against thresholds and the expert benchmark; 409 while it records.
ApiResponse session_review(ApiContext& ctx);
// admin: marks a finished, scored attempt as an expert run (or unmarks it); audited.
ApiResponse set_expert_run(ApiContext& ctx);
// Any role: per task and metric, the expert runs' n, mean, SD, median, p10, p90.
ApiResponse list_benchmarks(ApiContext& ctx);
// Any role: every metric a task may score, with its unit and one-line definition.
ApiResponse list_metrics(ApiContext& ctx);
// Curricula as JSON files (curriculum/curriculum_json.h): import (admin, 201; 422 naming the
// path of the first problem; 409 for a taken name), replace (admin: edit thresholds, tasks),
// export (admin, instructor: the definition as a download). Audited.
ApiResponse import_curriculum(ApiContext& ctx);
ApiResponse update_curriculum(ApiContext& ctx);
ApiResponse export_curriculum(ApiContext& ctx);
ApiResponse trainee_progress(ApiContext& ctx);
// instructors, admins: every trainee's progress (as trainee_progress) with their names, for the
// progress-at-a-glance table.
ApiResponse progress_overview(ApiContext& ctx);
// admin: the latest 200 audit entries, newest first.
ApiResponse list_audit(ApiContext& ctx);
ApiResponse list_curricula(ApiContext& ctx);
ApiResponse start_session(ApiContext& ctx);
ApiResponse get_session(ApiContext& ctx);
ApiResponse pause_session(ApiContext& ctx);
ApiResponse resume_session(ApiContext& ctx);
ApiResponse stop_session(ApiContext& ctx);

// Tissue calibration (admin; docs/calibration.md): the scenes it can fit and their example data
// (GET /api/calibration/example?scene=ID, a CSV download), jobs (POST: 201, the data checked
// first, 422 naming what is wrong and where; GET list and one with its result; POST .../cancel:
// 409 once ended) and the named materials saved from finished jobs (POST: 201, 409 for a taken
// name or an unfinished job; GET also for instructors, with the tasks that name each).
ApiResponse list_calibration_scenes(ApiContext& ctx);
ApiResponse calibration_example(ApiContext& ctx);
ApiResponse create_calibration_job(ApiContext& ctx);
ApiResponse list_calibration_jobs(ApiContext& ctx);
ApiResponse get_calibration_job(ApiContext& ctx);
ApiResponse cancel_calibration_job(ApiContext& ctx);
ApiResponse create_material(ApiContext& ctx);
ApiResponse list_materials(ApiContext& ctx);

}  // namespace incise::server::api
