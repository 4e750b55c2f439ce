#!/usr/bin/env python
# license removed for brevity
# The course's Python tf broadcaster (section 4.2.2.3), running on urdftk's `tf` without ROS.
# Only the rospy lines changed:
#   import rospy                          -> (gone)
#   rospy.init_node(...)                  -> (gone: no master; frames go out on Zenoh by default)
#   rospy.Rate(10) / rospy.Time.now()     -> tf.Rate(10) / tf.Time.now()
#   while not rospy.is_shutdown():        -> while True:  (Ctrl-C stops it)
#   except rospy.ROSInterruptException:   -> except KeyboardInterrupt:
# The course passes my_FrameName without defining it; it is defined here.
# Watch it from another terminal:  urdftk tf echo world my_FrameName
import tf

my_FrameName = "my_FrameName"

def myPublishFunction():
    my_transformBroadcaster = tf.TransformBroadcaster()

    rate = tf.Rate(10)

    x = 0.2;
    y = 0.25;
    z = 1;
    roll = 0.25;
    pitch = 0.1;
    yaw = 0.2;

    while True:
        my_transformBroadcaster.sendTransform((x, y, z),
                                              tf.transformations.quaternion_from_euler(roll, pitch, yaw),
                                              tf.Time.now(), my_FrameName, "world")
        rate.sleep()

if __name__ == '__main__':
    try:
        myPublishFunction()
    except KeyboardInterrupt:
        pass
