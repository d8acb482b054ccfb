/* test_pipeline_budget.c - the per-budget part of the pipeline (pipeline.h texopt_job_*):
 * one job writes several budgets exactly as separate runs would; a perceptual job keeps the
 * best of its candidate layouts (allocated, allocated denser than the input, uniform, and
 * the signal metrics' layouts, each the same as its baseline method's, refined beside stage
 * 1's when lower), and its closed-loop refinement gives the triangles with on-screen error
 * (lit when the material has a map besides base colour) more texels; the target_loss budget
 * returns a cost whose q meets the target while a cost one search step smaller does not;
 * bad targets are refused. Models are generated grids (grid_glb.h); the same checks on the
 * perceptual method are in test_pipeline_budget_slow.c. */
#include "evaluate.h"
#include "pipeline_budget_checks.h"

TEST(one_job_writes_each_budget_as_a_separate_run_would)
{
    check_job_reuse(TEXOPT_METHOD_TEWARI);
}

/* A candidate's q in the statistics' allocation_choice, INFINITY when it was not made. */
static double candidate_q(cJSON *choice, const char *key)
{
    cJSON *q = cJSON_GetObjectItem(choice, key);
    return cJSON_IsNumber(q) ? q->valuedouble : INFINITY;
}

/* The perceptual job's choice among its candidate layouts, from the statistics: the kept
 * one has the smallest q; the dense one (cap 1.5x input density) is made exactly when the
 * cap at input density bound a target of the allocated one; the signal metrics' ones are
 * made; the kept one's budget correction matches its kind (allocated: close to 1; uniform:
 * the whole magnification stage 1's targets needed). */
static void check_choice(cJSON *st, double relative_cost)
{
    cJSON *choice = cJSON_GetObjectItem(st, "allocation_choice");
    CHECK(choice != NULL);
    const char *names[] = {"allocated", "allocated_dense", "uniform", "hessian", "signal_stretch"};
    const char *keys[] = {"q_allocated", "q_allocated_dense", "q_uniform", "q_hessian", "q_signal_stretch"};
    double smallest = INFINITY, kept = NAN;
    cJSON *chosen = cJSON_GetObjectItem(choice, "chosen");
    CHECK(cJSON_IsString(chosen));
    const char *name = cJSON_IsString(chosen) ? chosen->valuestring : "";
    for (int i = 0; i < 5; i++) {
        double q = candidate_q(choice, keys[i]);
        smallest = fmin(smallest, q);
        if (strcmp(name, names[i]) == 0)
            kept = q;
    }
    CHECK(isfinite(candidate_q(choice, "q_hessian")) && isfinite(candidate_q(choice, "q_signal_stretch")));
    CHECK_MSG(kept == smallest, "kept %s at q %g, smallest %g", name, kept, smallest);
    int allocated = strcmp(name, "allocated") == 0, is_dense = strcmp(name, "allocated_dense") == 0;
    cJSON *dense = cJSON_GetObjectItem(choice, "q_allocated_dense");
    cJSON *seconds = cJSON_GetObjectItem(choice, "seconds");
    CHECK(number_at(seconds, "evaluate", NULL) > 0 && number_at(seconds, "other_candidate", NULL) > 0);
    cJSON *d = first_domain(st);
    double area_scale = number_at(d, "stage1", "area_scale_mean");
    double bs = number_at(d, "budget_scale", NULL);
    CHECK((cJSON_GetObjectItem(d, "allocation") != NULL) == (allocated || is_dense));
    if (allocated) /* the allocated candidate's own statistics: the dense one exists iff it capped */
        CHECK((dense != NULL) == (number_at(d, "allocation", "capped_share") > 0));
    if (allocated || is_dense) {
        CHECK(number_at(d, "allocation", "scale") > 1);
        CHECK(bs > 0.9 && bs < 1.1);
    } else if (strcmp(name, "uniform") == 0) {
        CHECK(bs > 0.9 * sqrt(relative_cost / area_scale));
    }
}

/* q of the written output against the input on one camera set, at 96 px. */
static double file_q(const scratch *s, texopt_camera_set cameras)
{
    texopt_model *in = load(s->in), *out = load(s->out);
    texopt_evaluate_options opt = {0};
    opt.resolution = 96;
    opt.cameras = cameras;
    texopt_evaluation ev;
    char err[256];
    int ok = in && out && texopt_evaluate(in, out, &opt, &ev, err, sizeof err) == TEXOPT_OK;
    texopt_model_destroy(in);
    texopt_model_destroy(out);
    return ok ? ev.q : NAN;
}

/* The choice is made on other views than the reported q's: the kept candidate's q is the
 * written file's on the icosahedron's 12 views, the reported q its q on the dodecahedron's 20
 * (each up to the PNG's 8-bit rounding, 2%), and the two differ by more than that (on a layout
 * where they do: at c_r 0.9 both came within 0.1% of each other once the re-bake was bounded). */
static void check_choice_views(const scratch *s, cJSON *st)
{
    cJSON *choice = cJSON_GetObjectItem(st, "allocation_choice");
    const char *name = cJSON_GetObjectItem(choice, "chosen")->valuestring;
    char key[64];
    snprintf(key, sizeof key, "q_%s", name);
    double chosen = candidate_q(choice, key), reported = number_at(st, "evaluation", "q");
    double choice_views = file_q(s, TEXOPT_CAMERAS_ICOSAHEDRON),
           reported_views = file_q(s, TEXOPT_CAMERAS_DODECAHEDRON);
    CHECK_MSG(fabs(choice_views - chosen) < 0.02 * chosen, "chosen at q %g, the file's on its views %g", chosen,
              choice_views);
    CHECK_MSG(fabs(reported_views - reported) < 0.02 * reported, "reported q %g, the file's %g", reported,
              reported_views);
    CHECK_MSG(fabs(chosen - reported) > 0.02 * reported, "chosen at q %g, reported %g", chosen, reported);
}

/* A perceptual job small enough for every build: one thread, 5 BO iterations, 96 px views;
 * the layout machinery alone, without the resize check (test_pipeline_resize.c), whose resize
 * these flat grids' layouts mostly do not beat. */
static texopt_params small_perceptual_job(double relative_cost)
{
    texopt_params p = {0};
    p.threads = 1;
    p.resize_check = -1;
    p.iterations = 5;
    p.relative_cost = relative_cost;
    p.eval_resolution = 96;
    return p;
}

TEST(perceptual_keeps_the_best_of_its_candidate_layouts)
{
    /* Half flat, half text: stage 1 shrinks the flat half far more than the budget does, so
     * the uniform candidate is magnified by the budget while the allocated one is solved at
     * about its final size. */
    scratch s;
    CHECK(scratch_init(&s, 4, 64, "half") == 0);
    texopt_params p = small_perceptual_job(0.9);
    p.evaluate = 1;
    p.refinements = -1; /* q is then the kept candidate's (the refinement: test below) */
    char err[512] = "";
    CHECK_OK(texopt_optimize_file(s.in, s.out, s.stats, &p, NULL, err, sizeof err), err);
    cJSON *st = read_json(s.stats);
    CHECK(st != NULL);
    CHECK_NEAR(number_at(first_domain(st), "relative_cost", NULL), 0.9, 0.01);
    CHECK(number_at(first_domain(st), "stage1", "area_scale_mean") < 0.7);
    check_choice(st, 0.9);
    /* At c_r 0.9 the text half's targets reach input density: the cap binds, so the dense
     * candidate is made and weighed. */
    CHECK(cJSON_GetObjectItem(cJSON_GetObjectItem(st, "allocation_choice"), "q_allocated_dense") != NULL);
    cJSON_Delete(st);
    /* A texture size: exact whichever candidate wins. */
    p.budget = TEXOPT_BUDGET_TEXTURE_SIZE;
    p.texture_width = 40;
    p.texture_height = 48;
    CHECK_OK(texopt_optimize_file(s.in, s.out, s.stats, &p, NULL, err, sizeof err), err);
    texopt_model *out = load(s.out);
    CHECK(out && out->images[0].width == 40 && out->images[0].height == 48);
    texopt_model_destroy(out);
    st = read_json(s.stats);
    double reached = number_at(first_domain(st), "relative_cost", NULL);
    check_choice(st, reached);
    check_choice_views(&s, st);
    cJSON_Delete(st);
    scratch_free(&s);
}

/* The statistics' evaluation q of one job on the scratch model, NAN on failure. */
static double job_q(const scratch *s, const texopt_params *p, cJSON **stats)
{
    char err[512] = "";
    *stats = NULL;
    if (texopt_optimize_file(s->in, s->out, s->stats, p, NULL, err, sizeof err) != TEXOPT_OK) {
        printf("  %s\n", err);
        return NAN;
    }
    *stats = read_json(s->stats);
    return *stats ? number_at(*stats, "evaluation", "q") : NAN;
}

/* Perceptual's metric candidates are the tewari and ssp methods' layouts at the same budget:
 * their q on the choice's views is those methods' written files' there, up to the PNG's 8-bit
 * rounding (measured 0.1%), so the layout it keeps is not worse than either on those views
 * (and here on the reported ones); with metric_candidates = -1 they are not made. On the
 * half-flat grid at c_r 0.3. */
TEST(the_metric_candidates_are_the_signal_metric_baselines_layouts)
{
    scratch s;
    CHECK(scratch_init(&s, 4, 64, "half") == 0);
    texopt_params p = small_perceptual_job(0.3);
    p.evaluate = 1;
    p.refinements = -1;
    cJSON *st = NULL;
    double q = job_q(&s, &p, &st);
    cJSON *choice = cJSON_GetObjectItem(st, "allocation_choice");
    double q_hessian = candidate_q(choice, "q_hessian"), q_stretch = candidate_q(choice, "q_signal_stretch");
    cJSON_Delete(st);
    double baseline[2], choice_views[2];
    const texopt_method methods[2] = {TEXOPT_METHOD_TEWARI, TEXOPT_METHOD_SSP};
    for (int m = 0; m < 2; m++) {
        texopt_params b = p;
        b.method = methods[m];
        baseline[m] = job_q(&s, &b, &st);
        choice_views[m] = file_q(&s, TEXOPT_CAMERAS_ICOSAHEDRON);
        cJSON_Delete(st);
    }
    printf("  perceptual q %.5f; hessian candidate %.5f, tewari %.5f (%.5f on the choice's views); signal_stretch "
           "%.5f, ssp %.5f (%.5f)\n",
           q, q_hessian, baseline[0], choice_views[0], q_stretch, baseline[1], choice_views[1]);
    CHECK_NEAR(q_hessian, choice_views[0], 0.005 * choice_views[0]);
    CHECK_NEAR(q_stretch, choice_views[1], 0.005 * choice_views[1]);
    CHECK(isfinite(q) && q <= baseline[0] && q <= baseline[1]);
    p.metric_candidates = -1;
    job_q(&s, &p, &st);
    choice = cJSON_GetObjectItem(st, "allocation_choice");
    CHECK(choice && !cJSON_GetObjectItem(choice, "q_hessian") && !cJSON_GetObjectItem(choice, "q_signal_stretch"));
    cJSON_Delete(st);
    scratch_free(&s);
}

/* One perceptual job on the checker grid at c_r `cost`, with or without the metric candidates:
 * the refinement's q after its rounds and its rounds; *metric_lower: the metric candidates'
 * best q was below stage 1's; *metric_kept: one of them was kept. */
static double refined_q(const scratch *s, double cost, int with, int *rounds, int *metric_lower, int *metric_kept)
{
    texopt_params p = small_perceptual_job(cost);
    p.eval_resolution = 128;
    p.metric_candidates = with ? 1 : -1;
    cJSON *st = NULL;
    job_q(s, &p, &st);
    cJSON *choice = cJSON_GetObjectItem(st, "allocation_choice");
    double q = number_at(choice, "refinement", "q_after");
    *rounds = (int)number_at(choice, "refinement", "rounds");
    double stage1 = fmin(candidate_q(choice, "q_allocated"),
                         fmin(candidate_q(choice, "q_allocated_dense"), candidate_q(choice, "q_uniform")));
    *metric_lower = fmin(candidate_q(choice, "q_hessian"), candidate_q(choice, "q_signal_stretch")) < stage1;
    cJSON *chosen = cJSON_GetObjectItem(choice, "chosen");
    *metric_kept = cJSON_IsString(chosen) &&
                   (strcmp(chosen->valuestring, "hessian") == 0 || strcmp(chosen->valuestring, "signal_stretch") == 0);
    cJSON_Delete(st);
    return q;
}

/* With the refinement on, a metric candidate whose q is lower than stage 1's best is refined
 * too, with twice the rounds, and kept only when its refined q (the refinement's cameras) is
 * lower. On a checker grid whose tewari and ssp layouts start below stage 1's at c_r 0.2 (on
 * the choice's views) and not at 0.1: the refined q with the metric candidates is at most that
 * without them, lower exactly when one is kept; measured, stage 1's refined layout stays at
 * 0.1 (0.16525 either way) and a metric one is kept at 0.2 (0.1415 against 0.1526). */
TEST(a_metric_candidate_is_refined_beside_stage_1_s_and_kept_when_lower)
{
    scratch s;
    CHECK(scratch_init(&s, 4, 128, "checker") == 0);
    const double costs[2] = {0.1, 0.2};
    int kept[2];
    for (int c = 0; c < 2; c++) {
        int rounds[2], lower[2], metric[2];
        double without = refined_q(&s, costs[c], 0, &rounds[0], &lower[0], &metric[0]);
        double with = refined_q(&s, costs[c], 1, &rounds[1], &lower[1], &metric[1]);
        kept[c] = metric[1];
        printf("  c_r %.1f: refined q %.5f without the metric candidates, %.5f with (%s kept, %d rounds)\n", costs[c],
               without, with, metric[1] ? "a metric one" : "stage 1's", rounds[1]);
        CHECK_MSG(lower[1] || !metric[1], "c_r %.1f: a metric candidate kept but not refined", costs[c]);
        CHECK_MSG(lower[1] == (c == 1), "c_r %.1f: the metric candidates started lower: %d", costs[c], lower[1]);
        CHECK(with <= without);
        CHECK((with < without) == metric[1]);
        CHECK_EQ_INT(rounds[1], metric[1] ? 2 * TEXOPT_DEFAULT_REFINEMENTS : TEXOPT_DEFAULT_REFINEMENTS);
        CHECK_EQ_INT(rounds[0], TEXOPT_DEFAULT_REFINEMENTS);
    }
    CHECK_MSG(!kept[0] && kept[1], "kept a metric candidate at c_r 0.1: %d, at 0.2: %d", kept[0], kept[1]);
    scratch_free(&s);
}

/* Share of the output texels (UV area times texture size) on triangles whose input UVs lie
 * in the detailed half (u > 0.5) of the "half" texture. */
static double detailed_share(const texopt_model *in, const texopt_model *out)
{
    double detailed = 0, total = 0;
    for (size_t t = 0; t < out->triangle_count; t++) {
        const uint32_t *v = &out->triangles[3 * t];
        const float *a = &out->uvs[2 * v[0]], *b = &out->uvs[2 * v[1]], *c = &out->uvs[2 * v[2]];
        double area = 0.5 * fabs((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]));
        double u = (in->uvs[2 * v[0]] + in->uvs[2 * v[1]] + in->uvs[2 * v[2]]) / 3;
        total += area;
        detailed += u > 0.5 ? area : 0;
    }
    return detailed / total;
}

/* q of out against in on a camera set, at res px, lit or of base colour; -1 when it cannot
 * be measured. */
static double q_on(const texopt_model *in, const texopt_model *out, texopt_camera_set cameras, int lit, int res)
{
    texopt_evaluate_options eo = {.resolution = res, .threads = 1, .cameras = cameras, .lit = lit};
    texopt_evaluation ev;
    char err[256] = "";
    return texopt_evaluate(in, out, &eo, &ev, err, sizeof err) == TEXOPT_OK ? ev.q : -1;
}

/* The closed-loop refinement (job_refine.c) on an 8 x 8 grid whose detail (text)
 * lies on the u > 0.5 half of base colour, or, with mr_pattern, of the metallic-roughness map
 * only: the on-screen error (base colour's, or lit when the material has that map) is on the
 * text, so the refined layout gives the text half more of the same budget, and its loss on
 * the cameras it was tuned on (the icosahedron's) is lower. relative_cost: the budget, small
 * enough that the rounds find something to move (base colour's grid at 0.8 left them none
 * once the re-bake's fit kept the reduced half's detail: no round kept; at 0.3 the text half
 * went from 83% to 87% of the texels). */
static void check_refinement(const char *pattern, const char *mr_pattern, double relative_cost)
{
    int lit = mr_pattern != NULL;
    scratch s;
    CHECK(scratch_init(&s, 8, 128, pattern) == 0);
    CHECK(write_grid_glb_images(s.in, 8, 128, pattern, mr_pattern) == 0);
    texopt_params p = small_perceptual_job(relative_cost);
    p.refinements = -1;
    /* The paper's threshold, whose targets leave the rounds something to find here: with the
     * default 0.03 the rounds on this grid lower base colour's 12-view q by under 1% (0.04842
     * -> 0.04805), with 0.01 by 8% (0.0413 -> 0.0379). */
    p.epsilon = 0.01;
    /* 128 texels at the default screen (1.25 pixels per texel side). On 64 texels the rounds
     * moved q by about the layout's noise: at 96 px the luma difference kept one round 3%
     * lower and the edge measure none, at 160 and 192 px the luma difference kept none
     * (BENCHMARKS.md@9f788a8 "The refinement steered by edges"). */
    p.eval_resolution = 160;
    /* Refining stage 1's layout: the hessian candidate, kept here otherwise, already gives
     * the text 93% of the texels, and its rounds lowered q (0.0446 -> 0.0428) moving 0.3%. */
    p.metric_candidates = -1;
    char err[512] = "";
    CHECK_OK(texopt_optimize_file(s.in, s.out, NULL, &p, NULL, err, sizeof err), err);
    p.refinements = 0; /* the default rounds */
    p.refine_lit = lit ? 1 : -1;
    CHECK_OK(texopt_optimize_file(s.in, s.again, s.stats, &p, NULL, err, sizeof err), err);
    cJSON *st = read_json(s.stats);
    cJSON *rounds = cJSON_GetObjectItem(cJSON_GetObjectItem(st, "allocation_choice"), "refinement");
    CHECK(rounds != NULL);
    double kept = number_at(rounds, "kept", NULL);
    cJSON *measure = cJSON_GetObjectItem(rounds, "measure");
    CHECK(cJSON_IsString(measure) && strcmp(measure->valuestring, lit ? "lit" : "baseColor") == 0);
    CHECK_NEAR(number_at(rounds, "rounds", NULL), TEXOPT_DEFAULT_REFINEMENTS, 0);
    CHECK(kept >= 1 && kept <= TEXOPT_DEFAULT_REFINEMENTS);
    CHECK(number_at(rounds, "q_after", NULL) < number_at(rounds, "q_before", NULL));
    CHECK(number_at(rounds, "seconds", NULL) > 0);
    CHECK_NEAR(number_at(st, "params", "refinements"), TEXOPT_DEFAULT_REFINEMENTS, 0);
    cJSON *asked = cJSON_GetObjectItem(cJSON_GetObjectItem(st, "params"), "refine_by");
    CHECK(cJSON_IsString(asked) && strcmp(asked->valuestring, lit ? "lit" : "baseColor") == 0);
    cJSON_Delete(st);
    texopt_model *in = load(s.in), *plain = load(s.out), *refined = load(s.again);
    CHECK(in && plain && refined);
    if (in && plain && refined) {
        double before = detailed_share(in, plain), after = detailed_share(in, refined);
        double q_before = q_on(in, plain, TEXOPT_CAMERAS_ICOSAHEDRON, lit, p.eval_resolution);
        double q_after = q_on(in, refined, TEXOPT_CAMERAS_ICOSAHEDRON, lit, p.eval_resolution);
        printf("  %s: detailed share %.4f -> %.4f, q %.5f -> %.5f\n", lit ? "lit" : "base colour", before, after,
               q_before, q_after);
        CHECK_MSG(after > before + 0.02, "detailed share %.4f -> %.4f", before, after);
        CHECK(q_after >= 0 && q_after < q_before);
    }
    texopt_model_destroy(in);
    texopt_model_destroy(plain);
    texopt_model_destroy(refined);
    scratch_free(&s);
}

/* Share of the output texels on the u > 0.5 half of an 8 x 8 grid whose base colour is flat
 * with text in its alpha on that half ("flat|half"), under alphaMode `mode`; -1 on failure. */
static double cut_out_detailed_share(const char *mode)
{
    scratch s;
    char material[160], err[512] = "";
    const char *patterns[1] = {"flat|half"};
    snprintf(material, sizeof material,
             "{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}},"
             "\"alphaMode\":\"%s\"}",
             mode);
    double share = -1;
    if (scratch_init(&s, 8, 64, NULL) != 0)
        return -1;
    texopt_params p = small_perceptual_job(0.5);
    if (write_grid_glb_material(s.in, 8, 64, patterns, 1, material) == 0 &&
        texopt_optimize_file(s.in, s.out, NULL, &p, NULL, err, sizeof err) == TEXOPT_OK) {
        texopt_model *in = load(s.in), *out = load(s.out);
        share = in && out ? detailed_share(in, out) : -1;
        texopt_model_destroy(in);
        texopt_model_destroy(out);
    }
    scratch_free(&s);
    return share;
}

/* Text cut out of a flat surface (alphaMode MASK) keeps the texels a colour text would; as
 * OPAQUE the same file is flat everywhere and neither half is preferred. Either reader of the
 * alpha suffices here (stage 1 alone: 0.775, the evaluation's choice and rounds alone: 0.825,
 * both: 0.825, with the choice on the dodecahedron's views; 0.693 on the icosahedron's); with
 * neither, as before 1e60ff9, MASK gave 0.500 too. */
TEST(a_cut_out_keeps_its_texels_end_to_end)
{
    double mask = cut_out_detailed_share("MASK"), opaque = cut_out_detailed_share("OPAQUE");
    printf("  text half's share of the texels: MASK %.3f, OPAQUE %.3f\n", mask, opaque);
    CHECK_MSG(mask > 0.65, "MASK %g", mask);
    CHECK_MSG(opaque > 0.3 && opaque < 0.6, "OPAQUE %g", opaque);
}

/* stats.json's stage1.close_up_triangles (triopt.h): 2 x 2 quads on 512 texels are larger
 * than stage 1's window at its zoom limit, all 8 triangles (test_triopt); 4 x 4 quads on 64
 * texels fit it, none. */
TEST(stage1_statistics_count_the_triangles_with_close_ups)
{
    static const struct {
        int quads, texels;
        double triangles;
    } cases[] = {{2, 512, 8}, {4, 64, 0}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        scratch s;
        CHECK(scratch_init(&s, cases[i].quads, cases[i].texels, "half") == 0);
        texopt_params p = small_perceptual_job(0.5);
        p.refinements = -1;
        char err[512] = "";
        CHECK_OK(texopt_optimize_file(s.in, s.out, s.stats, &p, NULL, err, sizeof err), err);
        cJSON *st = read_json(s.stats);
        CHECK(st != NULL);
        CHECK_NEAR(number_at(first_domain(st), "stage1", "close_up_triangles"), cases[i].triangles, 0);
        cJSON_Delete(st);
        scratch_free(&s);
    }
}

TEST(refinement_moves_texels_to_the_detailed_half)
{
    check_refinement("half", NULL, 0.3);
}

/* Base colour flat, the metallic-roughness map half text, refine_lit: base colour's error
 * shows nothing to move, the lit render's does. */
TEST(refinement_reads_the_lit_render_when_the_material_has_other_maps)
{
    check_refinement("flat", "half", 0.8);
}

/* The saved model at path (a grid whose second image repeats base colour's pixels) holds two
 * images of one size, smaller than the input's 64, with the same pixels. */
static void check_twin_images(const char *path)
{
    texopt_model *out = load(path);
    int two = out && out->image_count == 2;
    const texopt_image *a = two ? &out->images[0] : NULL, *b = two ? &out->images[1] : NULL;
    int same_size =
        two && a->width < 64 && a->width == b->width && a->height == b->height && a->channels == b->channels;
    int same_pixels =
        same_size && memcmp(a->pixels, b->pixels, sizeof(float) * a->width * a->height * a->channels) == 0;
    texopt_model_destroy(out);
    CHECK(two);
    CHECK(same_size);
    CHECK(same_pixels);
}

/* The candidates bake only base colour for the choice; the kept one's other images are baked
 * afterwards into its own layout: an image with base colour's pixels comes out identical. */
TEST(perceptual_bakes_every_image_into_the_kept_layout)
{
    scratch s;
    CHECK(scratch_init(&s, 4, 64, "half") == 0);
    CHECK(write_grid_glb_images(s.in, 4, 64, "half", "half") == 0);
    texopt_params p = small_perceptual_job(0.5);
    char err[512] = "";
    CHECK_OK(texopt_optimize_file(s.in, s.out, s.stats, &p, NULL, err, sizeof err), err);
    check_twin_images(s.out);
    /* A baseline bakes both images after its layout, on two threads side by side (one
     * thread each): the same images as one after the other. */
    p.method = TEXOPT_METHOD_TEWARI;
    CHECK_OK(texopt_optimize_file(s.in, s.out, NULL, &p, NULL, err, sizeof err), err);
    p.threads = 2;
    CHECK_OK(texopt_optimize_file(s.in, s.again, NULL, &p, NULL, err, sizeof err), err);
    CHECK(same_output(s.out, s.again));
    check_twin_images(s.again);
    cJSON *st = read_json(s.stats);
    cJSON *rounds = cJSON_GetObjectItem(cJSON_GetObjectItem(st, "allocation_choice"), "refinement");
    CHECK(rounds != NULL);
    /* A metallic-roughness map and refine_lit left to its default: the lit render's screen. */
    cJSON *measure = cJSON_GetObjectItem(rounds, "measure");
    CHECK(cJSON_IsString(measure) && strcmp(measure->valuestring, "lit") == 0);
    cJSON_Delete(st);
    scratch_free(&s);
}

/* The lit refinement's rounds draft the images base colour's evaluation does not read
 * (prefilter only); the saved model has them baked again with the fit: an image with base
 * colour's pixels comes out identical to base colour, as without the lit refinement. */
TEST(lit_refinement_saves_no_draft)
{
    scratch s;
    CHECK(scratch_init(&s, 4, 64, "half") == 0);
    CHECK(write_grid_glb_images(s.in, 4, 64, "half", "half") == 0);
    texopt_params p = small_perceptual_job(0.5);
    p.refine_lit = 1;
    char err[512] = "";
    CHECK_OK(texopt_optimize_file(s.in, s.out, s.stats, &p, NULL, err, sizeof err), err);
    cJSON *st = read_json(s.stats);
    cJSON *measure =
        cJSON_GetObjectItem(cJSON_GetObjectItem(cJSON_GetObjectItem(st, "allocation_choice"), "refinement"), "measure");
    CHECK(cJSON_IsString(measure) && strcmp(measure->valuestring, "lit") == 0);
    cJSON_Delete(st);
    check_twin_images(s.out);
    scratch_free(&s);
}

TEST(target_loss_finds_the_smallest_cost_meeting_the_target)
{
    check_target_loss(TEXOPT_METHOD_INPUT, 0.08);
}

TEST(target_loss_out_of_range_is_refused)
{
    scratch s;
    CHECK(scratch_init(&s, 1, 16, "flat") == 0);
    texopt_params p = {0};
    p.budget = TEXOPT_BUDGET_TARGET_LOSS;
    char err[512] = "";
    double bad[] = {0, -0.1, 1, 2, NAN};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        p.target_loss = bad[i];
        CHECK(texopt_optimize_file(s.in, s.out, NULL, &p, NULL, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
        CHECK(strstr(err, "target_loss") != NULL);
    }
    texopt_job *job = NULL;
    p.budget = TEXOPT_BUDGET_RELATIVE_COST;
    CHECK_OK(texopt_job_create(&job, s.in, &p, NULL, err, sizeof err), err);
    texopt_job_budget b = {TEXOPT_BUDGET_TARGET_LOSS, 0, 0, 0, 3};
    CHECK(texopt_job_write(job, &b, s.out, NULL, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(texopt_job_write(job, NULL, s.out, NULL, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    texopt_job_destroy(job);
    CHECK(access(s.out, F_OK) != 0);
    scratch_free(&s);
}
