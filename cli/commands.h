/* Every plumage subcommand: int run(int argc, char **argv), where argv[0]
 * is the subcommand's name. Each returns the process exit status. */
#ifndef PLUMAGE_CLI_COMMANDS_H
#define PLUMAGE_CLI_COMMANDS_H

int cmd_probe(int argc, char **argv);
int cmd_bench(int argc, char **argv);
int cmd_render(int argc, char **argv);
int cmd_batch(int argc, char **argv);
int cmd_generate(int argc, char **argv);
int cmd_texture(int argc, char **argv);
int cmd_params(int argc, char **argv);
int cmd_fireflies(int argc, char **argv);
int cmd_export(int argc, char **argv);
int bench_generate(int argc, char **argv);
int bench_render(int argc, char **argv);
int bench_scene(int argc, char **argv);
int bench_export(int argc, char **argv);
int probe_masking(int argc, char **argv);
int bench_masking(int argc, char **argv);
int probe_fiber(int argc, char **argv);
int probe_bcsdf(int argc, char **argv);
int probe_layout(int argc, char **argv);
int probe_visibility(int argc, char **argv);
int bench_fiber(int argc, char **argv);

#endif
